"""OscillatorRun (the stepping object behind CoulombOscillator.fmu and the sweep drivers): a
snapshot is the complete state, so a restored run continues bit for bit as the original."""
import itertools

from frictionjoint.stepping import OscillatorRun


def test_restore_mid_run_continues_bit_identically():
    for f, w, x0 in itertools.product((0.1, 0.5, 0.7), (0.45, 1.5, 2.5), (0.0, 50.0)):
        p = dict(slip_force=f, force_amplitude=1.0, omega=w, x0=x0)
        a = OscillatorRun(p)
        a.advance(7.3)
        snap = a.snapshot()
        v_scale = a._marcher.v_scale
        a.advance(41.0)  # the marcher's velocity scale (its event tolerances) moves on
        a.restore(snap)
        assert a._marcher.v_scale == v_scale
        a.advance(60.0)
        b = OscillatorRun(p)
        b.advance(7.3)
        b.advance(60.0)
        for name in ("x", "v", "friction_force", "dissipated_energy", "event_count", "stuck"):
            assert a.output(name) == b.output(name), (f, w, x0, name)
        assert a.log.time == b.log.time and a.log.kind == b.log.kind
