"""The binding's overhead, measured in one run: the criterion medians of the Rust benches
`psh_rotate/vector/100` and `psh_project/cube64/16` (benches/polarized.rs, run here by
`cargo bench`) and the same operations from Python by `timeit` on inputs of the same
sizes, alternated for ROUNDS rounds (a shared 2-vCPU machine drifts by 10-20% between
runs of a few seconds; the medians over rounds compare like with like), and the fixed
cost of one call (the same calls on the smallest inputs).

    python python/benches/overhead.py          # from the repository root, psh installed

Prints a Markdown table (Rust median, Python median, overhead) and exits non-zero only if
a measurement could not be made (timing is reported, never asserted).
"""

import json
import pathlib
import subprocess
import sys
import timeit

import numpy as np

import psh

ROOT = pathlib.Path(__file__).resolve().parents[2]
IDS = ["psh_rotate/vector/100", "psh_project/cube64/16"]
ROUNDS = 5


def criterion_medians():
    subprocess.run(["cargo", "bench", "--bench", "polarized", "--",
                    "psh_rotate/vector/100|psh_project/cube64/16"], cwd=ROOT, check=True,
                   stdout=subprocess.DEVNULL)
    out = {}
    for i in IDS:
        group, function = i.split("/", 1)
        # criterion's directory of a benchmark id: the group, then the function with '/'
        # replaced by '_'.
        est = ROOT / "target" / "criterion" / group / function.replace("/", "_") / "new" / "estimates.json"
        out[i] = json.loads(est.read_text())["median"]["point_estimate"] * 1e-9
    return out


def python_medians(repeat=15):
    rng = np.random.default_rng(1)
    # As the Rust benches: an RGB POLAR4 vector of l < 100 rotated by the same rotation
    # (Wigner blocks included), and an RGB 64^2 cube cross of physical Stokes vectors to
    # l < 16.
    c = rng.normal(size=(3, 100 * 100, 4))
    c[:, :4, 1:3] = 0
    v = psh.PshVector(c)
    r = psh.Rotation.from_rotvec([0.3, -1.1, 0.7])
    u = rng.uniform(-1, 1, size=(3, 192, 256, 4))
    cube = np.stack([2 + u[..., 0], 0.5 * u[..., 1], 0.5 * u[..., 2], 0.2 * u[..., 3]], axis=-1)
    tasks = {
        IDS[0]: lambda: v.rotated(r),
        IDS[1]: lambda: psh.project_map(cube, 15),
    }
    out = {}
    for i, f in tasks.items():
        f()
        times = timeit.repeat(f, number=1, repeat=repeat)
        out[i] = float(np.median(times))
    return out


def fixed_costs(repeat=2000):
    """Seconds per call on the smallest inputs: an l = 0 vector, an l = 0 projection of a
    3 x 4 cube cross."""
    v = psh.PshVector(np.ones((3, 1, 4)) * [1, 0, 0, 1])
    r = psh.Rotation.from_rotvec([0.3, -1.1, 0.7])
    cube = np.ones((3, 3, 4, 4))
    return {
        IDS[0]: min(timeit.repeat(lambda: v.rotated(r), number=repeat, repeat=5)) / repeat,
        IDS[1]: min(timeit.repeat(lambda: psh.project_map(cube, 0), number=repeat, repeat=5)) / repeat,
    }


def main():
    rounds = []
    for _ in range(ROUNDS):
        rounds.append((criterion_medians(), python_medians()))
    fixed = fixed_costs()
    print("| operation | Rust, criterion medians per round | Python, timeit medians per round "
          "| median Rust | median Python | overhead | fixed cost of a call |")
    print("|---|---|---|---|---|---|---|")
    for i in IDS:
        rust = [r[i] for r, _ in rounds]
        py = [p[i] for _, p in rounds]
        mr, mp = float(np.median(rust)), float(np.median(py))
        print(f"| `{i}` | {', '.join(f'{t * 1e3:.1f}' for t in rust)} ms "
              f"| {', '.join(f'{t * 1e3:.1f}' for t in py)} ms | {mr * 1e3:.2f} ms "
              f"| {mp * 1e3:.2f} ms | {100 * (mp / mr - 1):+.1f}% | {fixed[i] * 1e6:.1f} us |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
