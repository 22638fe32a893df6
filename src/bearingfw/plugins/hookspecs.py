"""Hook specifications: everything a bearingfw plugin can contribute.

A plugin is a module (or any object) with functions marked ``@bearingfw.hookimpl`` whose names
are the hooks below. bearingfw finds plugins through the entry-point group ``bearingfw``; its
own built-in plugins are found the same way. In a plugin's ``pyproject.toml``::

    [project.entry-points.bearingfw]
    my-laws = "my_package.laws"      # a module with @bearingfw.hookimpl functions

Each hook returns a list of contributions. bearingfw checks each contribution on its own: a bad
one is reported (``bearingfw plugins``) together with the plugin's name and does not stop the
rest from loading.
"""

from __future__ import annotations

import pluggy

hookspec = pluggy.HookspecMarker("bearingfw")
hookimpl = pluggy.HookimplMarker("bearingfw")


@hookspec
def bearingfw_register_laws():
    """Return a list of bearing-law classes.

    Each class is called with the user's parameters (``bearingfw.create_law(name, **params)``)
    and must produce an object satisfying :class:`bearingfw.BearingLaw`: ``name``, ``dims``,
    ``rigid``, ``initial_state(n)`` and ``respond(state, u, normal_force, dt)``. ``name`` must be a
    class attribute (the registry key, unique across all plugins); ``dims`` and ``rigid`` may
    be class attributes or constructor parameters. The constructor's keyword parameters are the
    law's parameters; attrs fields made with :func:`bearingfw.parameter` also carry their
    allowed range and unit into ``bearingfw plugins``.
    """


@hookspec
def bearingfw_register_record_readers():
    """Return a list of ground-motion record readers, one per file format.

    A reader is a :class:`bearingfw.plugins.contracts.RecordReader` (re-exported as
    ``bearingfw.motion.RecordReader``) or any object with the same members:

    - ``name`` (str): the registry key, unique across all plugins, e.g. ``"peer-at2"``; users
      choose a reader by it (``bearingfw record info --format NAME``);
    - ``suffixes`` (tuple of str): file-name endings with the dot, matched case-insensitively,
      e.g. ``(".at2",)``;
    - ``read(path, *, dt=None, units=None)``: returns a list of :class:`bearingfw.motion.Trace`
      (values, dt in s, units ``"g"``, ``"m/s^2"`` or ``"cm/s^2"``, label), one per acceleration
      component, in the file's order; ``dt`` and ``units`` are the user's overrides for formats
      that do not state them. On a malformed file it raises
      :class:`bearingfw.motion.RecordFormatError` naming the file and the line;
    - optionally ``sniff(path) -> bool``: whether the file looks like this format (used to
      confirm a suffix match, and for files whose suffix no reader claims);
    - optionally ``description`` (str): one line for ``bearingfw plugins``.

    bearingfw converts the units to m/s^2, resamples to a common time step, pads unequal
    lengths with zeros and assembles the components (horizontal 1, horizontal 2, vertical).
    """


@hookspec
def bearingfw_register_intensity_scales():
    """Return a list of :class:`bearingfw.plugins.contracts.IntensityScale` objects.

    A scale is data, not code (``bearingfw.motion.IntensityScale``, the same class): a unique
    ``name``, the degree labels lowest first, the t_Ha breakpoints (s) and, per degree, the
    inclusive upper bound of PGA_H10 (m/s^2) at each breakpoint (linear in between, constant
    outside). The constructor checks the table (shapes, positive bounds increasing from degree
    to degree); a scale that fails is reported by ``bearingfw plugins``.
    """


@hookspec
def bearingfw_register_presets():
    """Return a list of :class:`bearingfw.plugins.contracts.BearingPreset` objects (re-exported as
    ``bearingfw.BearingPreset``).

    A preset is a named bearing model for the sliding bearings of a bridge built from presets
    (the reference bridge, and any builder that asks the registry): ``law(bearing)`` gets a
    :class:`~bearingfw.plugins.contracts.PresetBearing` (the bearing's name, the stick stiffness
    K_s, the friction coefficient and, when ``needs_dead_load``, its dead-load normal force) and
    returns ``(law name, parameters)`` for that bearing, or None to fix it (JOIN). A law package
    contributes the preset of its own law here, so that ``[models.X] preset = "..."`` runs it.
    """


@hookspec
def bearingfw_register_metrics():
    """Return a list of metric families for the experiment runner.

    A metric family is an object with a unique ``name`` (str) and the members documented in
    :mod:`bearingfw.experiment.metrics` (unit, what it reads from a cell's results, how it reduces
    to one number, its note in the report). The registry only checks the ``name``.
    """


@hookspec
def bearingfw_register_executors():
    """Return a list of executors for the experiment runner (``bearingfw run --executor NAME``).

    An executor is an object with a unique ``name`` (str) and the members documented in
    :mod:`bearingfw.experiment.executors`. The registry only checks the ``name``.
    """
