"""Matrices: USD (row vectors, translation in the last row) -> IR (column vectors, rows)."""

from __future__ import annotations

import numpy as np


def to_numpy(m) -> np.ndarray:
    """A Gf.Matrix4d as the IR's column-vector 4x4 numpy matrix (the transpose)."""
    return np.array(m, dtype=np.float64).reshape(4, 4).T


def ir_matrix(m: np.ndarray) -> list[list[float]]:
    return [[float(v) for v in row] for row in m]


def split_scale(m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rigid matrix with unit axes, per-axis scale lengths)."""
    s = np.linalg.norm(m[:3, :3], axis=0)
    r = m.copy()
    r[:3, :3] = m[:3, :3] / np.where(s > 0, s, 1.0)
    return r, s
