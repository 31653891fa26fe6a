"""One module per notebook: `check(claims)` asserts the numbers the notebook
printed, read from the `<name>_claims.json` it writes next to its figures."""
