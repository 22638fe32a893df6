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
