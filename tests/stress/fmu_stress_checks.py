"""FMU stress checks, one FMU per process (pythonfmu FMUs cannot be instantiated twice in one
process: NTNU-IHB/PythonFMU #213, #228); the instance is reused through ``initialize``, which
resets it. Usage:

    python tests/stress/fmu_stress_checks.py CHECK FMU_PATH [JSON ...]  -> prints one JSON object
"""
import json
import math
import sys
import time

from frictionjoint.fmi.master import FMUInstance


class RawInstance(FMUInstance):
    """An FMUInstance that hands values to the FMU as they are (NaN, inf, 5.5 for an Integer):
    the library's master refuses those itself, these checks test the FMU's own refusal."""

    _SETTERS = {"Real": ("setReal", lambda name, value: float(value)),
                "Integer": ("setInteger", lambda name, value: int(value)),
                "Boolean": ("setBoolean", lambda name, value: bool(value))}


def bad_parameters(path, cases):
    """Initialise with each parameter set of the JSON list ``cases`` in turn (each should fail),
    then once with the defaults and one step (which must work after the failures)."""
    out = []
    with RawInstance(path) as inst:
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
    with RawInstance(path) as inst:
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


def _status(call):
    """``call()``'s FMI status (0 ok, 2 discard, 3 error, 4 fatal) and its seconds."""
    from fmpy.fmi1 import FMICallException

    t = time.perf_counter()
    try:
        call()
        status = 0
    except FMICallException as exc:
        status = exc.status
    return status, time.perf_counter() - t


def careless_host(path, cases):
    """For each case of the JSON list ``cases`` ({"params": ..., "steps": [h, ...], "terminate":
    before which step index or null, "read": [output names]}), from a fresh initialisation: each
    doStep's raw status and seconds (a refused step does not advance the time), then the outputs
    read at the end (or the status of the read) and the FMU log."""
    out = []
    with RawInstance(path) as inst:
        fmu = inst._fmu
        for case in json.loads(cases):
            inst.initialize(case.get("params", {}))
            inst.messages.clear()
            t, steps = 0.0, []
            for i, h in enumerate(case["steps"]):
                if case.get("terminate") == i:
                    steps.append({"terminate": _status(fmu.terminate)[0]})
                status, seconds = _status(lambda: fmu.doStep(t, h))
                steps.append({"status": status, "seconds": seconds})
                if status == 0:
                    t += h
            values = error = None
            try:
                values = inst.get(case.get("read", []))
            except Exception as exc:  # FMUError: the status of the read, in its message
                error = str(exc)
            out.append({"steps": steps, "t": t, "values": values, "read_error": error,
                        "messages": list(inst.messages)})
    return {"cases": out}


def extreme_values(path, cases):
    """For each case of the JSON list ``cases`` ({"params": ..., "inputs": ..., "h": step}): set the
    parameters, initialise, set the inputs, read every Real output, step once and read them again.
    Returns per case: the initialisation's error (or None), the reads (values or the read's error)
    and the step's raw status, with the FMU log."""
    from fmpy.fmi1 import FMICallException

    out = []
    with RawInstance(path) as inst:
        names = [v.name for v in inst.model.modelVariables if v.causality == "output" and v.type == "Real"]
        fmu = inst._fmu
        for case in json.loads(cases):
            row = {"init": None, "reads": [], "step": None}
            inst.messages.clear()
            try:
                inst.initialize(case.get("params", {}))
            except Exception as exc:  # FMUError with the log
                row["init"] = str(exc)
                row["messages"] = list(inst.messages)
                out.append(row)
                continue
            try:
                inst.set(case.get("inputs", {}))
            except Exception as exc:
                row["init"] = f"set: {exc}"
            for when in ("before", "after"):
                if when == "after":
                    row["step"], _ = _status(lambda: fmu.doStep(0.0, case.get("h", 1e-3)))
                try:
                    vals = fmu.getReal([inst.vr[n] for n in names])
                    row["reads"].append({"values": dict(zip(names, vals)), "error": None})
                except FMICallException as exc:
                    row["reads"].append({"values": None, "error": exc.status})
            row["messages"] = list(inst.messages)
            out.append(row)
    return {"cases": out}


if __name__ == "__main__":
    print(json.dumps(globals()[sys.argv[1]](*sys.argv[2:])), flush=True)
