"""The notebooks as Jupyter runs them: each `notebooks/NAME.py` (jupytext percent
format, the form that diffs) is paired with `notebooks/NAME.ipynb` (the form a
repository page shows, committed with its outputs: figures inline). `execute(name,
out)` runs the notebook's cells in a Jupyter kernel (nbclient, `python3`), its files
written to `out` (`ROTORJAX_NOTEBOOK_OUT`), and returns the executed notebook;
`python -m tests.notebook_run [NAME ...]` refreshes the committed `.ipynb` files
(outputs included) from the `.py` files."""

import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOTEBOOKS = os.path.join(ROOT, "notebooks")


def source(name):
    """The notebook read from its `.py` form (jupytext)."""
    import jupytext

    return jupytext.read(os.path.join(NOTEBOOKS, f"{name}.py"))


def execute(name, out, timeout=900):
    """`name`'s notebook executed in a fresh `python3` kernel, in `out`."""
    from nbclient import NotebookClient

    nb = source(name)
    env = dict(os.environ, ROTORJAX_NOTEBOOK_OUT=str(out), PYTHONPATH=ROOT + os.pathsep
               + os.environ.get("PYTHONPATH", ""))
    old = dict(os.environ)
    os.environ.update(env)      # the kernel inherits this process's environment
    try:
        NotebookClient(nb, timeout=timeout, kernel_name="python3", resources={"metadata": {"path": str(out)}}).execute()
    finally:
        os.environ.clear()
        os.environ.update(old)
    return nb


def write(name):
    import nbformat

    with tempfile.TemporaryDirectory() as out:
        nb = execute(name, out)
    for cell in nb.cells:       # what depends on the machine and the run, not on the notebook
        cell.get("metadata", {}).pop("execution", None)
    nbformat.write(nb, os.path.join(NOTEBOOKS, f"{name}.ipynb"))


if __name__ == "__main__":
    names = sys.argv[1:] or sorted(f[:-3] for f in os.listdir(NOTEBOOKS) if f.endswith(".py"))
    for n in names:
        write(n)
        print("wrote", os.path.join(NOTEBOOKS, f"{n}.ipynb"))
