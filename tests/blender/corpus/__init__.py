"""The Cycles parity corpus (see scenes.py, make_references.py, compare.py)."""
