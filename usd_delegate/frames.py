"""usdrecord frame lists (the core's CLI parses ``--frames`` itself; this is for Python use)."""


def parse_frames(spec: str) -> list[float]:
    """``7``, ``1,5,9``, ``1:10`` or ``1:10x2`` (and comma lists of those)."""
    out: list[float] = []
    for part in spec.split(","):
        if ":" in part:
            a, rest = part.split(":", 1)
            b, _, step = rest.partition("x")
            a, b, st = float(a), float(b), float(step or 1)
            if st <= 0 or b < a:
                raise ValueError(f"--frames `{part}`: expected start:end with end >= start")
            n = int((b - a) / st + 1e-9)
            out.extend(a + i * st for i in range(n + 1))
        else:
            out.append(float(part))
    return out
