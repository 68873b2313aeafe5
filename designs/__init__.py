"""Wheel designs shipped with the tool (TOML files, installed as package data):
``table1.toml`` is the default; see README "Swapping a wheel design"."""
