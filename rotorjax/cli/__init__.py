"""The `rotorjax` command: a thin layer over the public functions, one module per
group of commands (`_simulate`, `_stability`, `_flexible`, `_contact`, `_continue`,
`_balance`, `_info`), the shared checks in `_common`, the parser and exit codes in
`_main`."""

from ._main import build_parser as build_parser
from ._main import main as main
from ._simulate import summarize as summarize
