"""The built-in ground-motion plugin: the record readers and the default intensity scale.

Registered through the ``bearingfw`` entry point (``builtin-motion``) exactly like a third-party
plugin, so that users can add readers and scales the same way.
"""

from bearingfw.motion.intensity import DEFAULT_SCALE
from bearingfw.motion.readers import AT2_READER, COLUMNS_READER, KNET_READER, NPZ_READER
from bearingfw.plugins.hookspecs import hookimpl


@hookimpl
def bearingfw_register_record_readers():
    # In the order files of an unclaimed suffix are sniffed: K-NET before the columns reader, whose
    # sniffer takes any file with a row of numbers (a K-NET file's data) for a column file.
    return [AT2_READER, KNET_READER, COLUMNS_READER, NPZ_READER]


@hookimpl
def bearingfw_register_intensity_scales():
    return [DEFAULT_SCALE]
