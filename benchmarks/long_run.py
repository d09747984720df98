"""Long-run drift of the exact marcher on a stop-free Coulomb oscillator (issue 5).

Marches ``CoulombOscillator(slip_force=0.3, force_amplitude=1.0, omega=0.8)`` for N periods
(default 1e5) from its periodic orbit (shooting, ``steady_state``) and reports

* the relative error of the state ``(x, v)`` at ``t = N T`` against the orbit's initial state;
* the amplitude over the last period -- exact peaks: ``x`` at the velocity-reversal events
  (``v = 0``, located by the marcher to rounding), not samples -- against Den Hartog's closed
  form (:func:`frictionjoint.analytic.den_hartog_response`);
* the run time and the cost per event.

Usage: ``python benchmarks/long_run.py [N] [--out benchmarks/results_long_run.txt]``
"""
from __future__ import annotations

import argparse
import platform
import time

import numpy as np

import frictionjoint as fj
from frictionjoint.analytic import den_hartog_response
from frictionjoint.solvers.marcher.events import EventLog, Marcher


def main(argv=None) -> str:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("periods", nargs="?", type=int, default=100_000)
    ap.add_argument("--out", default=None, help="also write the report to this file")
    args = ap.parse_args(argv)
    n_per = args.periods

    osc = fj.CoulombOscillator(slip_force=0.3, force_amplitude=1.0, omega=0.8)
    period = osc.period
    ss = osc.steady_state()
    z0 = np.asarray(ss.initial_state, dtype=float)
    dh = den_hartog_response(osc.mass, osc.stiffness, osc.slip_force, osc.force_amplitude, osc.omega)

    m = Marcher(osc.system)
    state = m.initial_state(z0[0], z0[1])
    log = EventLog()
    t_start = time.perf_counter()
    m.march(state, (n_per - 1) * period, log)
    # last period: the peaks of |x| are at the velocity reversals (v = 0), which are events
    peaks = []

    def on_interval(itv, tau):
        x, v = itv.state(tau)
        peaks.append((itv.t0 + tau, float(x[0, 0]), float(v[0, 0])))

    m.march(state, n_per * period, log, on_interval=on_interval)
    elapsed = time.perf_counter() - t_start
    n_events = len(log)

    z_end = np.concatenate([state.x, state.v])
    drift = float(np.linalg.norm(z_end - z0) / np.linalg.norm(z0))
    t_last = (n_per - 1) * period
    rev = [(t, x, v) for t, x, v in peaks if t < n_per * period]  # ends of event-terminated pieces
    amp = max(abs(x) for _, x, _ in rev)
    v_at_peak = max(abs(v) for _, _, v in rev)
    amp_err = abs(amp - dh.amplitude) / dh.amplitude
    amp_ss_err = abs(ss.amplitude - dh.amplitude) / dh.amplitude

    lines = [
        "Long-run drift of the exact marcher (benchmarks/long_run.py)",
        f"case: CoulombOscillator(slip_force=0.3, force_amplitude=1.0, omega=0.8), m = k = 1, "
        f"period T = {period:.15g} s",
        f"Den Hartog regime: {dh.regime if hasattr(dh, 'regime') else 'n/a'}",
        f"periods N = {n_per}, events = {n_events} ({n_events / n_per:.3g} per period), "
        f"stick/slip kinds: {sorted(set(log.kind))}",
        f"periodic orbit at t = 0 (shooting): x0 = {z0[0]:.17g}, v0 = {z0[1]:.17g}",
        f"state at t = N T:                   x  = {z_end[0]:.17g}, v  = {z_end[1]:.17g}",
        f"drift |z(NT) - z0| / |z0| = {drift:.3e}",
        f"amplitude over the last period [{t_last:.6g}, {n_per * period:.6g}] s (x at v = 0, "
        f"max |v| there {v_at_peak:.1e}): {amp:.17g}",
        f"Den Hartog closed form:          {dh.amplitude:.17g}",
        f"relative amplitude error = {amp_err:.3e} (steady_state at t = 0: {amp_ss_err:.3e})",
        f"run time {elapsed:.2f} s, {elapsed / max(n_events, 1) * 1e6:.1f} us per event "
        f"({platform.python_implementation()} {platform.python_version()}, numpy {np.__version__})",
    ]
    report = "\n".join(lines)
    print(report)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(report + "\n")
    return report


if __name__ == "__main__":
    main()
