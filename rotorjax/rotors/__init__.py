"""Rotor files shipped with rotorjax (TOML, SI units): `rotorjax.models._rotor_file.shipped_rotor(name)`
gives a file's path. See `rotorjax/models/_rotor_file.py` for the tables."""
