"""Checks of the numbers notebooks/identification.py prints (see tests/test_notebooks.py)."""

REQUIRED = False


def check(claims):
    raise NotImplementedError
