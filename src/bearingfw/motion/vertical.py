"""Is a component vertical? Evidence from its file name, its file's own label, and its amplitudes.

A vertical component fed to a horizontal axis changes a bridge's response without a word, so
:func:`~bearingfw.motion.load_directional` refuses it unless the user says it is meant. Three kinds
of evidence, each named in the message:

- **file name**: the last token of the file's stem (split at anything but letters and digits)
  or the letters after its last digit is a vertical code: ``V``, ``UP``, ``UD``, ``DWN``, ``DN``,
  ``DOWN``, ``Z``, ``VER``, ``VERT``, ``VRT``, ``VERTICAL``, or a SEED channel code ending in Z
  (``HNZ``, ``HHZ``, ``BHZ``, ...): ``RSN1633_MANJIL_ABBAR--V.AT2``, ``RSN4843_CHUETSU_65006UD.AT2``,
  ``NORTHR_SYL-UP.AT2``, ``station_HNZ.csv``. Only for a file that holds one component (the name of
  a three-column file says nothing about one column).
- **header / label**: the label the reader found in the file is such a code: the component named
  at the end of line 2 of a PEER ``.AT2`` header (``Chuetsu-oki, 7/16/2007, Matsushiro Tokamachi,
  UD``), a column name (``az``, ``acc_z [g]``, ``UP``) or an ``.npz`` array name (``v``).
- **amplitudes**, when other components of the same event are given: the component's peak is at
  most :data:`PGA_RATIO` of every other component's and its dominant frequency at least
  :data:`FREQUENCY_RATIO` times every other's, as a vertical's typically is (the Chuetsu-oki UD:
  0.65 m/s^2 at 3.3 Hz against 1.9 and 1.8 m/s^2 at 1.7 and 1.5 Hz). Near a source a vertical can
  be as strong as the horizontals (Manjil, Abbar: V 5.3 m/s^2, L 5.0, T 4.9): the amplitudes then
  say nothing, and the names and headers must.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

import attrs

__all__ = [
    "FREQUENCY_RATIO",
    "PGA_RATIO",
    "VERTICAL_CODES",
    "Evidence",
    "amplitude_evidence",
    "is_vertical_code",
    "label_evidence",
    "name_evidence",
]

#: Component codes that mean "vertical" (compared upper-case).
VERTICAL_CODES = frozenset({"V", "UP", "UD", "DWN", "DN", "DOWN", "Z", "VER", "VERT", "VRT", "VERTICAL"})

# SEED channel codes: band, instrument, orientation Z (HNZ, HHZ, BHZ, EHZ, HLZ, HGZ, ...).
_SEED_VERTICAL = re.compile(r"^[A-Z][HLNGM]Z$")
# A column or array name: an optional "a"/"acc"/"accel" before the code ("az", "acc_z", "accel-up").
_LABEL_PREFIX = re.compile(r"^(?:A|ACC|ACCEL|ACCELERATION)(?=[A-Z]+$)")

#: Amplitude evidence: the peak at most this fraction of every other given component's peak ...
PGA_RATIO = 0.6
#: ... and the dominant frequency at least this multiple of every other component's.
FREQUENCY_RATIO = 1.5


@attrs.frozen
class Evidence:
    """One reason to think a component is vertical: ``kind`` ("file name", "header", "label",
    "amplitudes") and ``reason`` (a clause for the error message)."""

    kind: str
    reason: str


def is_vertical_code(code: str) -> bool:
    """True if ``code`` (one token, any case) is a vertical component code."""
    code = code.strip().upper()
    return code in VERTICAL_CODES or bool(_SEED_VERTICAL.match(code))


def _tokens(text: str) -> list[str]:
    return [t for t in re.split(r"[^A-Za-z0-9]+", text.upper()) if t]


def _tail_code(token: str) -> str:
    """The letters after the last digit of ``token`` ("65006UD" -> "UD"), else the token itself."""
    match = re.search(r"\d([A-Z]+)$", token)
    return match[1] if match else token


def name_evidence(path: str | Path) -> Evidence | None:
    """Evidence from the file name (see the module docstring), or None."""
    tokens = _tokens(Path(path).stem)
    if not tokens:
        return None
    code = _tail_code(tokens[-1])
    if is_vertical_code(code):
        return Evidence("file name", f"its file name {Path(path).name!r} ends in {code!r}, a vertical component code")
    return None


def label_evidence(label: str, *, header: Sequence[str] | None = None, what: str = "label") -> Evidence | None:
    """Evidence from the label a reader found (PEER header line 2, column or array name), or None.

    ``header``: the file's PEER header lines, to quote line 2 in the reason.
    """
    tokens = _tokens(label)
    if not tokens:
        return None
    code = _LABEL_PREFIX.sub("", tokens[-1]) if len(tokens) == 1 else tokens[-1]
    if not is_vertical_code(code):
        # "VERTICAL ACC", "UD (m/s2)": a word that cannot be anything but vertical, anywhere.
        code = next((t for t in tokens if len(t) > 1 and t in VERTICAL_CODES), "")
        if not code:
            return None
    if header is not None and len(header) >= 2:
        return Evidence("header", f"its PEER header names the component {code!r} (line 2: {header[1].strip()!r})")
    return Evidence("label", f"its {what} {label!r} is a vertical component code")


def amplitude_evidence(pga: float, frequency: float | None, others: Sequence[tuple[str, float, float | None]]) -> Evidence | None:
    """Evidence from the amplitudes: ``pga`` (m/s^2) and dominant ``frequency`` (Hz) of the
    component against ``others``, ``(name, pga, frequency)`` of the other given components of the
    event. None without others or when either test fails (see :data:`PGA_RATIO`, :data:`FREQUENCY_RATIO`).
    """
    others = [o for o in others if o[1] > 0 and o[2] is not None]
    if not others or frequency is None or pga <= 0:
        return None
    if any(pga > PGA_RATIO * o[1] or frequency < FREQUENCY_RATIO * o[2] for o in others):
        return None
    compared = ", ".join(f"{name}: {p:.3g} m/s^2 at {f:.3g} Hz" for name, p, f in others)
    return Evidence(
        "amplitudes",
        f"its peak {pga:.3g} m/s^2 is at most {PGA_RATIO:g} of the other components' and its dominant frequency "
        f"{frequency:.3g} Hz at least {FREQUENCY_RATIO:g} times theirs ({compared}), as a vertical's typically is",
    )
