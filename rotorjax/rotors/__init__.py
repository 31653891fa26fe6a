"""Rotor files shipped with rotorjax (TOML, SI units): `rotorjax.io.shipped_rotor(name)` gives a
file's path. See `rotorjax/io/__init__.py` for the tables."""
