"""What the drop cases share (Fang's drops, King & Lind's Re = 4 drop): W*(t*) and H*(t*) of
several runs, the times of the width's extrema, how far a width retracts, the volume kept."""
import common


def run_drops(case, runs, diameter, speed, marks, title, filename, names=("D", "V")):
    """runs: [(label, scene file, overrides)]; marks: [(t*, text)] the paper states; names: the
    paper's symbols of the diameter and the speed.
    Measures per run the first maximum of W* after impact and the minimum after it, the largest
    retraction of W* below its running maximum and the largest |volume_error|, and keeps the
    series t*, W*, H* (keys t, w, h); draws W* and H* into `filename` unless it is None."""
    found = {}
    for label, scene, overrides in runs:
        s, _ = case.run(scene, label, overrides)
        t = [x * speed / diameter for x in s["time"]]
        w = [x / diameter for x in s["drop_width"]]
        h = [x / diameter for x in s["drop_height"]]
        # After impact (the width first grows past 1.05 D) the first maximum and the minimum
        # following it.
        t_impact = next((ti for ti, wi in zip(t, w) if wi > 1.05), t[-1])
        maxima = common.local_extrema(t, w, "max", t_impact)
        t_max = maxima[0] if maxima else float("nan")
        minima = common.local_extrema(t, w, "min", t_max) if maxima else []
        t_min = minima[0] if minima else float("nan")
        running, retraction = 0.0, 0.0
        for wi in w:
            running = max(running, wi)
            retraction = max(retraction, running - wi)
        volume = max(abs(v) for v in s["volume_error"])
        found[label] = dict(t_max=t_max, t_min=t_min, retraction=retraction, volume=volume,
                            w_end=w[-1], t=t, w=w, h=h)
    if filename is None:
        return found
    plt = common.figure()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.8))
    for label, r in found.items():
        ax1.plot(r["t"], r["w"], label=label)
        ax2.plot(r["t"], r["h"], label=label)
    for tm, text in marks:
        for ax in (ax1, ax2):
            ax.axvline(tm, color="0.5", ls=":", lw=1)
        ax1.text(tm, ax1.get_ylim()[1], text, rotation=90, va="top", ha="right", fontsize=7)
    d, v = names
    ax1.set(xlabel=f"t* = t {v} / {d}", ylabel=f"W* = width / {d}", title=f"{title}: width")
    ax2.set(xlabel=f"t* = t {v} / {d}", ylabel=f"H* = height / {d}", title=f"{title}: height")
    ax1.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(case.out / filename, dpi=110)
    return found


def newtonian_and_oldroyd_b(case, marks, title, filename, names, texts, timing):
    """A case of a Newtonian and an Oldroyd-B drop (newtonian.toml, oldroyd_b.toml) at 20 per
    diameter (short) or 20 and 40 (full): runs both, draws them (unless filename is None), and
    measures per resolution what `timing(n, oldroyd_b)` adds, the retraction of either drop and
    the volume kept. texts: what the paper's text says of the Newtonian spreading and of the
    volume ("" if nothing). Returns run_drops' measurements and series, by label
    ("newtonian 20", "oldroyd_b 40", ...)."""
    d = names[0]
    resolutions = [20] if case.short else [20, 40]
    runs = []
    for n in resolutions:
        runs += [(f"newtonian {n}", "newtonian.toml", {"particles_per_diameter": n}),
                 (f"oldroyd_b {n}", "oldroyd_b.toml", {"particles_per_diameter": n})]
    found = run_drops(case, runs, 0.02, 1.0, marks, title, filename, names)
    newtonian_text, volume_text = texts
    for n in resolutions:
        ob, nw = found[f"oldroyd_b {n}"], found[f"newtonian {n}"]
        timing(n, ob)
        case.measured(f"oldroyd_b_{n}_retraction",
                      f"Oldroyd-B, {n}/{d}: largest retraction of W*", ob["retraction"],
                      "{:.3f}")
        case.measured(f"newtonian_{n}_retraction", f"Newtonian, {n}/{d}: largest retraction "
                      f"of W* (text: {newtonian_text})", nw["retraction"], "{:.4f}")
        for label, r in (("newtonian", nw), ("oldroyd_b", ob)):
            case.measured(f"{label}_{n}_volume", f"{label}, {n}/{d}: largest "
                          f"abs(volume_error){volume_text}", r["volume"], "{:.4f}")
    return found
