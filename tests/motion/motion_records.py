"""The real records the motion tests read, and an independent AT2 reading."""

from pathlib import Path

#: The project's copy of the PEER records (see examples/data/records/README.md).
RECORDS = Path(__file__).resolve().parents[2] / "examples" / "data" / "records"
CHUETSU = [RECORDS / f"RSN4843_CHUETSU_65006{c}.AT2" for c in ("EW", "NS", "UD")]
MANJIL = [RECORDS / f"RSN1633_MANJIL_ABBAR--{c}.AT2" for c in ("L", "T", "V")]
G = 9.80665


def at2_values(path: Path) -> list[float]:
    """An independent reading of an .AT2 file for the tests: skip the 4 header lines, parse every token."""
    lines = path.read_bytes().decode("ascii").split("\r\n")
    return [float(token) for line in lines[4:] for token in line.split()]
