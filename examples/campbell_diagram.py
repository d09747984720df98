"""Campbell diagram of the Ti-64 compressor blade on its dovetail root.

The blade of ``models/ti64_compressor_blade.toml`` (Ti-6Al-4V, 150 mm, on a dovetail root that rocks
on two flat flanks, design speed 1000 rad/s) is assembled at each rotor speed: its centrifugal
stiffening and the flanks' normal load (the blade's centrifugal force) follow the speed. The
diagram shows its three lowest modes with the root stuck and with the root slipping freely, the
engine orders 1-8 and their crossings (located by root finding between the speeds), and the
nonlinear mode of each stuck mode at 5e-5 m of root motion (first harmonic of ``w0``): the root
slips at low speed, where its normal load is small, and sticks at high speed.

Usage::

    python examples/campbell_diagram.py [PNG] [SPEEDS]

writes the figure to PNG (default ``campbell_ti64.png``) and prints the crossings as a Markdown table
and the time taken; SPEEDS (or the environment variable ``FRICTIONJOINT_EXAMPLE_POINTS``) sets the
number of rotor speeds from 50 to 1500 rad/s (default 59).
"""
import os
import sys
import time

from frictionjoint.campbell import campbell

MODEL = "ti64_compressor_blade"
ENGINE_ORDERS = range(1, 9)
AMPLITUDE = 5e-5  # [m], first harmonic of the root's tangential DOF w0


def main(argv):
    path = argv[1] if len(argv) > 1 else "campbell_ti64.png"
    n = int(argv[2]) if len(argv) > 2 else int(os.environ.get("FRICTIONJOINT_EXAMPLE_POINTS", "59"))
    start = time.perf_counter()
    cd = campbell(MODEL, f"50:1500:{n}", engine_orders=ENGINE_ORDERS, n_modes=3, amplitude=AMPLITUDE)
    seconds = time.perf_counter() - start
    print(cd.table(markdown=True))
    print()
    print(cd.message)
    print(f"{n} speeds in {seconds:.1f} s")
    cd.plot(path=path)
    print(f"wrote {path}")
    return 0 if cd.success else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
