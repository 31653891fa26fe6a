"""Checks of the numbers notebooks/parameter_study.py prints (see tests/test_notebooks.py)."""

REQUIRED = False


def check(claims):
    raise NotImplementedError
