"""docs/settings.md is what scripts/gen_settings_doc.py writes from the installed package's
settings schema: a setting's documentation, default or range changed in the core fails here
until the page is generated again."""

from __future__ import annotations

import copy
import importlib.util
import os

import pytest

from conftest import ROOT

SCRIPT = os.path.join(ROOT, "scripts", "gen_settings_doc.py")
FIX = "run `python scripts/gen_settings_doc.py` (with the photonmap package installed)"


@pytest.fixture()
def gen():
    spec = importlib.util.spec_from_file_location("gen_settings_doc", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_settings_doc_is_up_to_date(gen):
    diff = gen.difference()
    assert diff is None, f"docs/settings.md is out of date: {FIX}.\n{diff}"


def test_check_names_a_changed_default(gen, monkeypatch, tmp_path, capsys):
    """The check bites: the page of the real schema passes, and one default changed in the
    schema is reported with its line."""
    page = tmp_path / "settings.md"
    page.write_text(gen.generate(), encoding="utf-8")
    assert gen.difference(page) is None
    assert gen.main(["--check", "--out", str(page)]) == 0

    schema = gen.load_schema()
    changed = copy.deepcopy(schema)
    seed = next(f for f in changed if f["name"] == "seed")
    seed["default"] = seed["default"] + 12345
    monkeypatch.setattr(gen, "load_schema", lambda: changed)

    diff = gen.difference(page)
    assert diff is not None and "differs" in diff
    assert "12345" in diff, diff
    capsys.readouterr()
    assert gen.main(["--check", "--out", str(page)]) == 1
    err = capsys.readouterr().err
    assert "settings.md:" in err and "gen_settings_doc.py" in err, err


def test_check_names_a_changed_preset_value(gen, monkeypatch, tmp_path):
    page = tmp_path / "settings.md"
    page.write_text(gen.generate(), encoding="utf-8")
    real = gen.load_presets

    def presets(names):
        out = real(names)
        out["final"] = dict(out["final"], spp=out["final"]["spp"] + 1)
        return out

    monkeypatch.setattr(gen, "load_presets", presets)
    diff = gen.difference(page)
    assert diff is not None and "spp" in diff, diff
