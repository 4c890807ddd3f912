"""Side-by-side speed of two ViscoSPH builds, alternating, in one run (speed is a ratio measured
on the same machine at the same time, never an absolute figure carried between sessions).

Usage (the baseline as a CLI, or built from a commit into a worktree under --build-dir):
  python3 examples/compare_speed.py --base-cli A/viscosph --new-cli B/viscosph
      [--base-fmu A.fmu --new-fmu B.fmu] [--case NAME=SCENE.toml:T_END ...]
      [--threads 1,2] [--rounds 5] [--no-default]
  python3 examples/compare_speed.py --build-base 72e3362 --new-cli target/release/viscosph ...

Times (wall clock, whole process for the CLI, `simulate_fmu` for the FMU):
  * `viscosph run` of the default scene (Fang's Oldroyd-B drop to t* = 8), unless --no-default;
  * the default drop through the FMU with fmpy, to 0.16 s at a 1 ms communication step (when
    both FMUs are given);
  * each --case: `viscosph run SCENE --t-end T_END` on each thread count of --threads (set by
    RAYON_NUM_THREADS; a scene's own `threads` key wins, so leave it out), with the
    particle-steps/s the CLI reports (its stepping loop only) next to the whole process's time.
Prints the minimum and the median of each, and the ratio base / new of the minima.
"""
import argparse
import re
import resource
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def time_cli(exe, workdir, scene=None, t_end=None, threads=None):
    """Wall time of a whole `viscosph run`, and the particle-steps/s it reports (or None)."""
    out = os.path.join(workdir, "run")
    shutil.rmtree(out, ignore_errors=True)
    cmd = [exe, "run", "--out", out]
    if t_end is not None:
        cmd += ["--t-end", str(t_end)]
    if scene is not None:
        cmd.append(scene)
    env = dict(os.environ)
    if threads is not None:
        env["RAYON_NUM_THREADS"] = str(threads)
    u0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    u1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (u1.ru_utime - u0.ru_utime) + (u1.ru_stime - u0.ru_stime)
    m = re.search(r"\(([0-9.eE+-]+) particle-steps/s\)", r.stdout + r.stderr)
    return wall, cpu, (float(m.group(1)) if m else None)


def time_fmu(fmu):
    # A child process per run, so the two builds' libraries never share an interpreter.
    code = (
        "import time, fmpy\n"
        "t0 = time.perf_counter()\n"
        f"fmpy.simulate_fmu({fmu!r}, stop_time=0.16, output_interval=0.001,\n"
        "                  logger=lambda *a: None)\n"
        "print(time.perf_counter() - t0)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    return float(out.stdout.strip().splitlines()[-1])


def build_base(commit, build_dir):
    """The release CLI of `commit`, built in a worktree of this repository (the crate layout of
    old commits differs: the binary is built by name, whatever package holds it)."""
    repo = subprocess.run(["git", "rev-parse", "--show-toplevel"], check=True, capture_output=True,
                          text=True, cwd=os.path.dirname(os.path.abspath(__file__))).stdout.strip()
    src = os.path.join(build_dir, commit)
    if not os.path.isdir(src):
        subprocess.run(["git", "-C", repo, "worktree", "add", "--detach", src, commit], check=True)
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.join(src, "target"))
    subprocess.run(["cargo", "build", "--release", "--bin", "viscosph"], check=True, cwd=src, env=env)
    return os.path.join(src, "target", "release", "viscosph")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--base-cli", help="the baseline's CLI (or give --build-base)")
    ap.add_argument("--build-base", metavar="COMMIT",
                    help="build the CLI of COMMIT (a git worktree and target directory under "
                         "--build-dir, reused when already there) and use it as --base-cli")
    ap.add_argument("--build-dir", default=os.path.join(tempfile.gettempdir(), "viscosph-base"))
    ap.add_argument("--new-cli", required=True)
    ap.add_argument("--base-fmu")
    ap.add_argument("--new-fmu")
    ap.add_argument("--case", action="append", default=[],
                    help="NAME=SCENE.toml:T_END, a scene run to T_END by both builds")
    ap.add_argument("--threads", default="1", help="comma-separated thread counts of the --case runs")
    ap.add_argument("--no-default", action="store_true", help="skip the default scene's whole run")
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    if a.build_base:
        a.base_cli = build_base(a.build_base, a.build_dir)
    if not a.base_cli:
        ap.error("give --base-cli or --build-base")
    fmu = a.base_fmu is not None and a.new_fmu is not None
    cases = []  # (label, scene, t_end, threads)
    if not a.no_default:
        cases.append(("cli default scene", None, None, None))
    for c in a.case:
        name, rest = c.split("=", 1)
        scene, t_end = rest.rsplit(":", 1)
        for th in a.threads.split(","):
            cases.append((f"{name}, {th} thread(s)", os.path.abspath(scene), float(t_end), int(th)))
    times = {}
    cpus = {}
    rates = {}
    with tempfile.TemporaryDirectory() as work:
        for r in range(a.rounds):
            line = []
            for label, scene, t_end, th in cases:
                for which, exe in (("base", a.base_cli), ("new", a.new_cli)):
                    wall, cpu, rate = time_cli(exe, work, scene, t_end, th)
                    times.setdefault((label, which), []).append(wall)
                    cpus.setdefault((label, which), []).append(cpu)
                    if rate is not None:
                        rates.setdefault((label, which), []).append(rate)
                    line.append(f"{label} {which} {wall:.2f} s ({cpu:.2f} s CPU)")
            if fmu:
                for which, f in (("base", a.base_fmu), ("new", a.new_fmu)):
                    wall = time_fmu(f)
                    times.setdefault(("fmu default drop", which), []).append(wall)
                    line.append(f"fmu {which} {wall:.2f} s")
            print(f"round {r + 1}: " + ", ".join(line), flush=True)
    labels = [c[0] for c in cases] + (["fmu default drop"] if fmu else [])
    print(f"\nCPU: {cpu_model()}, {os.cpu_count()} logical CPUs; {a.rounds} alternating rounds")
    print("| case | base min [s] | base median [s] | new min [s] | new median [s] | base/new (min) "
          "| base max particle-steps/s | new max particle-steps/s | new/base "
          "| base min CPU [s] | new min CPU [s] | base/new (CPU) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for label in labels:
        b, n = times[(label, "base")], times[(label, "new")]
        rb, rn = rates.get((label, "base")), rates.get((label, "new"))
        extra = (f"{max(rb):.3e} | {max(rn):.3e} | {max(rn) / max(rb):.2f}" if rb and rn else "- | - | -")
        cb, cn = cpus.get((label, "base")), cpus.get((label, "new"))
        extra += (f" | {min(cb):.2f} | {min(cn):.2f} | {min(cb) / min(cn):.2f}" if cb and cn else " | - | - | -")
        print(f"| {label} | {min(b):.2f} | {statistics.median(b):.2f} | {min(n):.2f} | "
              f"{statistics.median(n):.2f} | {min(b) / min(n):.2f} | {extra} |")


if __name__ == "__main__":
    main()
