"""Ground motion: records, readers, PGA_H10 / Arias / t_Ha, intensity degrees, scaling, synthetic tremor.

Layer rule: this package may import the plugin layer, ``protocol`` and ``parameters``; nothing
below it (model, analysis) and nothing above it. Figures are in :mod:`bearingfw.motion.plot`
(imported on demand, it loads matplotlib).
"""

from bearingfw.motion.errors import IntensityMismatchError, RecordFormatError, UnknownReaderError, UnknownScaleError
from bearingfw.motion.intensity import (
    DEFAULT_LEVELS,
    DEFAULT_SCALE,
    DEFAULT_SCALE_NAME,
    LEVEL_NAMES,
    IntensityLevels,
    get_scale,
    level_degree,
    level_name,
    record_degree,
    scale_to_level,
    scale_to_pga_h10,
)
from bearingfw.motion.metrics import (
    ResponseSpectrum,
    arias_intensity,
    band_energy_fraction,
    dominant_frequency,
    fourier_spectrum,
    husid,
    lowpass,
    peak,
    pga_h10,
    record_summary,
    response_spectrum,
    significant_duration,
    t_ha,
)
from bearingfw.motion.readers import find_reader, read_at2, read_columns, read_npz, read_record
from bearingfw.motion.record import G, Record, Trace, assemble, normalize_units, resample
from bearingfw.motion.synthetic import TremorParameters, synthetic_tremor
from bearingfw.plugins.contracts import IntensityScale, RecordReader

__all__ = [
    "DEFAULT_LEVELS",
    "DEFAULT_SCALE",
    "DEFAULT_SCALE_NAME",
    "G",
    "LEVEL_NAMES",
    "IntensityLevels",
    "IntensityMismatchError",
    "IntensityScale",
    "Record",
    "RecordFormatError",
    "RecordReader",
    "ResponseSpectrum",
    "Trace",
    "TremorParameters",
    "UnknownReaderError",
    "UnknownScaleError",
    "arias_intensity",
    "assemble",
    "band_energy_fraction",
    "dominant_frequency",
    "find_reader",
    "fourier_spectrum",
    "get_scale",
    "husid",
    "level_degree",
    "level_name",
    "lowpass",
    "normalize_units",
    "peak",
    "pga_h10",
    "read_at2",
    "read_columns",
    "read_npz",
    "read_record",
    "record_degree",
    "record_summary",
    "resample",
    "response_spectrum",
    "scale_to_level",
    "scale_to_pga_h10",
    "significant_duration",
    "synthetic_tremor",
    "t_ha",
]
