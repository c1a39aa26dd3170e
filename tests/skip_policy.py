"""No silent skips on CI.

Every skipped test is listed at the end of the session with its reason. When ``CI`` is
``true`` (or ``PHOTONMAP_STRICT_SKIPS=1``), a skip fails the session unless its test is in
``ALLOWED_SKIPS`` below: scripts/test.sh installs every optional dependency (Dask, Open Image
Denoise, matplotlib, openjd-cli, Node.js, OpenImageIO) and the committed references are in
the repository, so on CI a test that skips because one of them is missing is a failure of
the setup, not a pass.

The conftest files of tests/python and tests/blender register this module as a plugin
(``register``).
"""

from __future__ import annotations

import fnmatch
import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent

# Skips that CI accepts: a pattern (fnmatch) on the test id relative to the repository
# (``tests/python/test_x.py::test_name[param]``; a module skipped at import is
# ``tests/python/test_x.py``), each with the reason it may skip there. Keep it short: every
# entry is a test that CI does not run.
ALLOWED_SKIPS: dict[str, str] = {}


def register(config) -> None:
    """Registers the hooks below once per session (from a conftest's ``pytest_configure``)."""
    me = sys.modules[__name__]
    if not config.pluginmanager.is_registered(me):
        config.pluginmanager.register(me, "photonmap-skip-policy")


def strict() -> bool:
    return os.environ.get("CI") == "true" or os.environ.get("PHOTONMAP_STRICT_SKIPS") == "1"


def repo_id(config, nodeid: str) -> str:
    """``nodeid`` (relative to pytest's rootdir) relative to the repository."""
    path, sep, rest = nodeid.partition("::")
    full = (Path(config.rootpath) / path).resolve()
    try:
        rel = full.relative_to(REPO).as_posix()
    except ValueError:  # a test outside the repository: its absolute path
        rel = full.as_posix()
    return rel + sep + rest


def allowed(test_id: str) -> str | None:
    """The allow-list's reason for skipping ``test_id``, or None."""
    for pattern, why in ALLOWED_SKIPS.items():
        if fnmatch.fnmatchcase(test_id, pattern):
            return why
    return None


# Skipped test ids (relative to pytest's rootdir) and their reasons, in order.
_SKIPS: dict[str, str] = {}


def _skip_reason(report) -> str:
    lr = report.longrepr
    if isinstance(lr, tuple) and len(lr) == 3:
        return str(lr[2]).removeprefix("Skipped: ")
    return str(lr)


def _record(report) -> None:
    if report.skipped and not hasattr(report, "wasxfail"):
        _SKIPS[report.nodeid] = _skip_reason(report)


def pytest_runtest_logreport(report):
    _record(report)


def pytest_collectreport(report):
    _record(report)


def _refused(config) -> list[tuple[str, str]]:
    out = []
    for nodeid, why in _SKIPS.items():
        tid = repo_id(config, nodeid)
        if allowed(tid) is None:
            out.append((tid, why))
    return out


def pytest_sessionfinish(session, exitstatus):
    if strict() and _refused(session.config):
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if not _SKIPS:
        return
    tr = terminalreporter
    tr.section("skipped tests")
    for nodeid, why in _SKIPS.items():
        tid = repo_id(config, nodeid)
        ok = allowed(tid)
        tr.line(f"SKIPPED {tid}: {why}" + (f" (allowed: {ok})" if ok else ""))
    refused = _refused(config)
    if refused and strict():
        tr.section("skips refused on CI", red=True, bold=True)
        for tid, why in refused:
            tr.line(f"{tid}: skipped ({why}), and not in ALLOWED_SKIPS "
                    f"(tests/skip_policy.py)", red=True)
        tr.line(f"{len(refused)} test(s) skipped on CI: the session fails.", red=True, bold=True)
    elif refused:
        tr.line(f"{len(refused)} test(s) skipped; with CI=true (or PHOTONMAP_STRICT_SKIPS=1) "
                f"the session would fail.", yellow=True)
