"""The stresses at a section's recovery points as one compiled loop (:func:`bearingfw.analysis.results.section_stresses`).

The same arithmetic as the array expressions it replaces, operation for operation (so the same
bits): a cell's stress histories (3,200 instants, two ends, several points) took a few
milliseconds per element as some thirty whole-array operations, most of the metrics' time.
"""

from __future__ import annotations

import math

from bearingfw.jit import kernel


@kernel("void(f8[:, ::1], f8[::1], f8[::1], f8[::1], f8[::1], f8[::1], f8[::1], f8, f8, f8, f8[:, ::1], f8[:, ::1], f8[:, ::1])")
def point_stresses(forces, y, z, r, torsion, shear_y, shear_z, area, iy, iz, sigma, tau, sigma1):
    """``forces`` (n, 6: N Vy Vz T My Mz); per point: ``y``, ``z``, ``r = hypot(y, z)``, the torsion
    and shear factors. Writes the normal stress, the shear stress and the maximum principal stress
    (n, points)."""
    for i in range(forces.shape[0]):
        n_, vy, vz, t, my, mz = forces[i, 0], forces[i, 1], forces[i, 2], forces[i, 3], forces[i, 4], forces[i, 5]
        for k in range(y.size):
            tau_t = torsion[k] * t
            if r[k] > 0.0:
                t_xy = shear_y[k] * vy - tau_t * z[k] / r[k]
                t_xz = shear_z[k] * vz + tau_t * y[k] / r[k]
                shear = math.hypot(t_xy, t_xz) + 0.0
            else:  # at the centroid: the torsion stress of the point as given
                t_xy = shear_y[k] * vy - 0.0
                t_xz = shear_z[k] * vz + 0.0
                shear = math.hypot(t_xy, t_xz) + abs(tau_t)
            normal = n_ / area + my * z[k] / iy - mz * y[k] / iz
            half = normal / 2
            radius = math.hypot(half, shear)
            sigma[i, k] = normal
            tau[i, k] = shear
            # principal_stress: the form that does not cancel for a compression
            sigma1[i, k] = shear * shear / (radius - half) if half < 0 else half + radius
