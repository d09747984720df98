"""Forced response of the Coulomb oscillator across resonance, beside Den Hartog's closed form.

Usage::

    python examples/forced_response.py [PLOT.png] [N_POINTS]

Sweeps the frequency ratio r = omega/omega_n from 0.5 to 2.5 up and down (stepped sine, the
exact periodic steady state at each frequency, started from the previous one), prints the table
(amplitude, Den Hartog amplitude, relative error or the regime where the closed form does not
apply) and writes the plot. ``FRICTIONJOINT_EXAMPLE_POINTS`` also sets the number of points.
"""
import os
import sys

import numpy as np

from frictionjoint.sweep import oscillator_sweep


def main(path="forced_response.png", points=60):
    mass, stiffness, force_amplitude = 1.0, 1.0, 1.0   # kg, N/m, N: omega_n = 1 rad/s
    slip_force = 0.5                                    # N: F/P0 = 0.5
    omegas = np.linspace(0.5, 2.5, points)             # rad/s (= r here)
    response = oscillator_sweep(mass, stiffness, slip_force, force_amplitude, omegas,
                                direction="both", progress=True)
    print(response.table())
    response.plot(path=path)
    print(f"wrote {path}")
    return response


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "forced_response.png"
    n = int(sys.argv[2]) if len(sys.argv) > 2 else int(os.environ.get("FRICTIONJOINT_EXAMPLE_POINTS", 60))
    main(out, n)
