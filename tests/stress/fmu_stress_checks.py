"""FMU stress checks, one FMU per process (pythonfmu FMUs cannot be instantiated twice in one
process: NTNU-IHB/PythonFMU #213, #228); the instance is reused through ``initialize``, which
resets it. Usage:

    python tests/stress/fmu_stress_checks.py CHECK FMU_PATH [JSON ...]  -> prints one JSON object
"""
import json
import math
import sys

from frictionjoint.fmi.master import FMUInstance


def bad_parameters(path, cases):
    """Initialise with each parameter set of the JSON list ``cases`` in turn (each should fail),
    then once with the defaults and one step (which must work after the failures)."""
    out = []
    with FMUInstance(path) as inst:
        for params in json.loads(cases):
            inst.messages.clear()
            try:
                inst.initialize(params)
                inst.step(0.1)
                raised = None
            except Exception as exc:  # fmpy's FMICallException
                raised = str(exc) or type(exc).__name__
            out.append({"raised": raised, "messages": list(inst.messages)})
        inst.messages.clear()
        try:
            inst.initialize({})
            inst.step(0.1)
            defaults_ok = True
        except Exception as exc:
            defaults_ok = f"{type(exc).__name__}: {exc} {inst.messages}"
    return {"cases": out, "defaults_ok": defaults_ok}


def extremes(path, cases):
    """CoulombOscillator.fmu: for each parameter set of the JSON list ``cases`` ({"params": ...,
    "periods": n, "steps": per period}), run n periods in communication steps of T/steps and
    return x, v, dissipated energy, event count at the end of each period, plus the FMU log."""
    out = []
    with FMUInstance(path) as inst:
        for case in json.loads(cases):
            inst.messages.clear()
            params = case["params"]
            period = 2 * math.pi / params["omega"]
            rows = []
            try:
                inst.initialize(params)
                n = int(case["steps"])
                for k in range(int(case["periods"]) * n):
                    inst.step(period / n)
                    if (k + 1) % n == 0:
                        rows.append(inst.get(["x", "v", "dissipated_energy", "event_count"]))
                error = None
            except Exception as exc:
                error = f"{type(exc).__name__}: {exc}"
            out.append({"rows": rows, "error": error, "messages": list(inst.messages)})
    return {"cases": out}


if __name__ == "__main__":
    print(json.dumps(globals()[sys.argv[1]](*sys.argv[2:])), flush=True)
