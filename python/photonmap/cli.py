"""The ``photonmap`` command. Arguments are parsed by the core's one clap definition
(``photonmap render --help``); USD stages are read here, by ``usd_delegate``.
``photonmap trade`` (speed against accuracy, ``photonmap.trade``) is Python's own;
``photonmap render ... --cluster`` renders on Dask (``photonmap.distributed``)."""

from __future__ import annotations

import json
import sys

from . import _core


def _usd_loader(diagnostics: list):
    def load(path, frame, camera, purposes, strict):
        import usd_delegate

        result = usd_delegate.load_stage(
            str(path), frame=frame, camera=camera, purposes=purposes, strict=strict
        )
        diagnostics.append(result)
        return json.dumps(result.ir_json_ready()), json.dumps(result.stats)

    return load


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["trade"]:
        from .trade import main as trade_main

        try:
            return trade_main(argv[1:])
        except KeyboardInterrupt:
            print("photonmap: interrupted", file=sys.stderr)
            return 130
    if argv[:1] == ["render"] and any(a == "--cluster" or a.startswith("--cluster=")
                                      for a in argv):
        from .distributed import main as distributed_main

        try:
            return distributed_main(argv)
        except KeyboardInterrupt:
            print("photonmap: interrupted", file=sys.stderr)
            return 130
    results: list = []
    try:
        from .denoise import CliDenoiser

        code = _core.run_cli(argv, _usd_loader(results), CliDenoiser())
    except KeyboardInterrupt:
        print("photonmap: interrupted", file=sys.stderr)
        code = 130
    except Exception as e:  # the importer's errors: one line, no traceback
        msg = str(e).strip().splitlines()
        print(f"photonmap: error: {msg[0] if msg else type(e).__name__}", file=sys.stderr)
        for line in msg[1:5]:
            print(f"  {line}", file=sys.stderr)
        code = 1
    _print_diagnostics(results)
    if argv[:1] in (["-h"], ["--help"]):
        print("\n  trade   Measure speed against accuracy of the settings (photonmap trade --help)")
    return code


def _print_diagnostics(results: list) -> None:
    seen = set()
    lines = []
    for r in results:
        for d in r.diagnostics.messages():
            if d not in seen:
                seen.add(d)
                lines.append(d)
    if lines:
        print(f"photonmap: {len(lines)} USD import note(s):", file=sys.stderr)
        for d in lines:
            print(f"  {d}", file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())
