"""Checks of the numbers notebooks/stability_boundaries.py prints (see tests/test_notebooks.py)."""

REQUIRED = False


def check(claims):
    raise NotImplementedError
