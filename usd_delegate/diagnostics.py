"""Import diagnostics: warnings and notes named by prim path, collected and reported once;
malformed data raises ``UsdImportError`` naming the prim."""

from __future__ import annotations


class UsdImportError(ValueError):
    """A stage that cannot be imported: the message names the file or the prim."""


class Diagnostics:
    """``warn`` for what is unsupported, approximated or missing (an error with ``strict``);
    ``note`` for faithful conversions worth knowing (a colour temperature applied)."""

    def __init__(self, strict: bool = False) -> None:
        self.strict = strict
        self.warnings: list[tuple[str, str]] = []
        self.notes: list[tuple[str, str]] = []

    def warn(self, prim, message: str) -> None:
        entry = (_path(prim), message)
        if entry not in self.warnings:
            self.warnings.append(entry)

    def note(self, prim, message: str) -> None:
        entry = (_path(prim), message)
        if entry not in self.notes:
            self.notes.append(entry)

    @staticmethod
    def error(prim, message: str) -> UsdImportError:
        return UsdImportError(f"{_path(prim)}: {message}")

    def messages(self) -> list[str]:
        return [f"warning: {p}: {m}" for p, m in self.warnings] + [
            f"note: {p}: {m}" for p, m in self.notes
        ]

    def finish(self) -> None:
        """With ``strict``, raises if there was any warning."""
        if self.strict and self.warnings:
            lines = "\n".join(f"{p}: {m}" for p, m in self.warnings)
            raise UsdImportError(
                f"{len(self.warnings)} warning(s) with --strict: {self.warnings[0][0]}: "
                f"{self.warnings[0][1]}\n{lines}"
            )


def _path(prim) -> str:
    if prim is None:
        return "<stage>"
    if isinstance(prim, str):
        return prim
    try:
        return str(prim.GetPath())
    except Exception:
        return str(prim)
