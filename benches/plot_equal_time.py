#!/usr/bin/env python3
"""Plots the JSON of benches/equal_time_cycles.py: per scene, RMSE and relMSE against seconds
for every preset of ours (add-on and USD) and every run of the Cycles peers.

    .venv-test/bin/python benches/plot_equal_time.py eq.json docs/equal_time_cycles.png

Needs matplotlib (the package's ``trade`` extra).
"""

from __future__ import annotations

import json
import sys

PEERS = {"cycles": ("Cycles", "tab:gray", "s"),
         "cycles_mnee": ("Cycles + shadow caustics", "tab:olive", "D"),
         "cycles_adaptive": ("Cycles adaptive", "tab:cyan", "v")}


def points(res: dict) -> dict[str, list[tuple[float, float, float]]]:
    """(seconds, RMSE, relMSE) per series, sorted by seconds."""
    out: dict[str, list] = {"ours (add-on)": [], "ours (USD)": []}
    for peer, runs in res.get("peer_runs", {}).items():
        out.setdefault(peer, []).extend((r["seconds"], r["rmse"], r["relmse"]) for r in runs)
    for row in res["rows"]:
        a = row["addon"]
        out["ours (add-on)"].append((a["seconds"], a["rmse"], a["relmse"]))
        if "usd" in row:
            u = row["usd"]
            out["ours (USD)"].append((u["seconds"], u["rmse"], u["relmse"]))
        for peer in PEERS:
            if peer in row:
                r = row[peer]
                # The run as measured (its own time), not the error brought to ours.
                k = r["seconds"] / max(r.get("at_seconds", r["seconds"]), 1e-9)
                out.setdefault(peer, []).append((r["seconds"], r["rmse"] / k ** 0.5,
                                                 r["relmse"] / k))
    return {k: sorted(v) for k, v in out.items() if v}


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    results = json.load(open(sys.argv[1]))
    names = list(results)
    fig, axes = plt.subplots(2, len(names), figsize=(4.2 * len(names), 7.0), squeeze=False)
    for col, name in enumerate(names):
        series = points(results[name])
        for row, (idx, label) in enumerate(((1, "RMSE"), (2, "relMSE"))):
            ax = axes[row][col]
            for key, pts in series.items():
                lab, colour, marker = PEERS.get(key, (key, None, "o"))
                if key.startswith("ours"):
                    colour = "tab:red" if "add-on" in key else "tab:orange"
                ax.plot([p[0] for p in pts], [p[idx] for p in pts], marker=marker,
                        color=colour, label=lab, lw=1.2, ms=4)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("seconds (whole render)")
            ax.set_ylabel(label)
            ax.grid(True, which="both", alpha=0.3)
            if row == 0:
                ax.set_title(name)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=90)


if __name__ == "__main__":
    main()
