"""Side-by-side speed of two ViscoSPH builds, alternating, in one run (speed is a ratio measured
on the same machine at the same time, never an absolute figure carried between sessions).

Usage:
  python3 examples/compare_speed.py --base-cli A/viscosph --new-cli B/viscosph \
      --base-fmu A.fmu --new-fmu B.fmu [--rounds 5]

Times (wall clock, whole process for the CLI, `simulate_fmu` for the FMU):
  * `viscosph run` of the default scene (Fang's Oldroyd-B drop to t* = 8);
  * the default drop through the FMU with fmpy, to 0.16 s at a 1 ms communication step.
Prints the minimum and the median of each, and the ratio base / new of the minima.
"""
import argparse
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


def time_cli(exe, workdir):
    out = os.path.join(workdir, "run")
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.perf_counter()
    subprocess.run([exe, "run", "--out", out], check=True, capture_output=True)
    return time.perf_counter() - t0


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


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--base-cli", required=True)
    ap.add_argument("--new-cli", required=True)
    ap.add_argument("--base-fmu", required=True)
    ap.add_argument("--new-fmu", required=True)
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    times = {k: [] for k in ["cli base", "cli new", "fmu base", "fmu new"]}
    with tempfile.TemporaryDirectory() as work:
        for r in range(a.rounds):
            times["cli base"].append(time_cli(a.base_cli, work))
            times["cli new"].append(time_cli(a.new_cli, work))
            times["fmu base"].append(time_fmu(a.base_fmu))
            times["fmu new"].append(time_fmu(a.new_fmu))
            print(f"round {r + 1}: " + ", ".join(f"{k} {v[-1]:.2f} s" for k, v in times.items()), flush=True)
    print(f"\nCPU: {cpu_model()}, {os.cpu_count()} logical CPUs; {a.rounds} alternating rounds")
    print("| case | base min [s] | base median [s] | new min [s] | new median [s] | base/new (min) |")
    print("|---|---|---|---|---|---|")
    for case in ["cli", "fmu"]:
        b, n = times[f"{case} base"], times[f"{case} new"]
        print(f"| {case} | {min(b):.2f} | {statistics.median(b):.2f} | {min(n):.2f} | "
              f"{statistics.median(n):.2f} | {min(b) / min(n):.2f} |")


if __name__ == "__main__":
    main()
