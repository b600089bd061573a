"""Executes the notebooks of this directory in order (nbclient, a fresh kernel each, from
this directory) and fails on the first error; prints each one's time.

    python docs/notebooks/run.py            # check: nothing is written
    python docs/notebooks/run.py --render   # also writes rendered/NAME.md and its figures

`--render` converts each executed notebook to Markdown with its outputs (nbconvert) into
`rendered/`, the copies the docs link to; the notebooks themselves stay without outputs
in git (`--strip` removes outputs and execution counts from them).
"""

import argparse
import pathlib
import sys
import time

import nbformat
from nbclient import NotebookClient

HERE = pathlib.Path(__file__).resolve().parent


def strip(nb):
    for cell in nb.cells:
        if cell.cell_type == "code":
            cell.outputs = []
            cell.execution_count = None
        cell.metadata = {}
    return nb


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--render", action="store_true")
    ap.add_argument("--strip", action="store_true")
    ap.add_argument("--timeout", type=int, default=300, help="seconds per cell")
    args = ap.parse_args()
    total = 0.0
    for path in sorted(HERE.glob("*.ipynb")):
        nb = nbformat.read(path, as_version=4)
        if args.strip:
            nbformat.write(strip(nb), path)
            continue
        start = time.monotonic()
        NotebookClient(nb, timeout=args.timeout, kernel_name="python3",
                       resources={"metadata": {"path": str(HERE)}}).execute()
        seconds = time.monotonic() - start
        total += seconds
        print(f"{path.name}: {seconds:.1f} s", flush=True)
        if args.render:
            from nbconvert import MarkdownExporter

            body, resources = MarkdownExporter().from_notebook_node(nb)
            out = HERE / "rendered"
            out.mkdir(exist_ok=True)
            stem = path.stem
            for name, data in resources.get("outputs", {}).items():
                (out / f"{stem}_{name}").write_bytes(data)
                body = body.replace(f"]({name})", f"]({stem}_{name})")
            (out / f"{stem}.md").write_text(body)
    if not args.strip:
        print(f"all notebooks: {total:.1f} s")


if __name__ == "__main__":
    sys.exit(main())
