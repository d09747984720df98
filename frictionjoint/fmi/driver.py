"""A sweep driver (:class:`frictionjoint.drivers.Driver`) on an oscillator FMU through fmpy."""
from __future__ import annotations

from pathlib import Path

from ..errors import ParameterError
from ..stepping import OSCILLATOR_OUTPUTS, OSCILLATOR_PARAMETERS

__all__ = ["FMUDriver"]


class FMUDriver:
    """``CoulombOscillator.fmu`` (or an FMU with the same variables) through fmpy: one instance in
    this process (:class:`~frictionjoint.fmi.master.FMUInstance`)."""

    def __init__(self, path):
        from .master import FMUInstance

        self.inst = FMUInstance(path)
        missing = [n for n in (*OSCILLATOR_PARAMETERS, "x", "v", "stuck") if n not in self.inst.vr]
        if missing:
            self.inst.close()
            raise ParameterError(f"model {Path(path).name} is not an oscillator FMU: it lacks the variables "
                                 f"{missing} (a sweep needs those of CoulombOscillator.fmu)")
        self.outputs = tuple(n for n in OSCILLATOR_OUTPUTS if n in self.inst.vr)

    def start(self, parameters: dict) -> None:
        self.inst.initialize(parameters)

    def advance(self, t: float) -> None:
        self.inst.step_to(t)

    def get(self, names) -> list:
        return self.inst.get(names)

    def save(self):
        return self.inst.get_state()

    def restore(self, saved) -> None:
        self.inst.set_state(saved)

    def close(self) -> None:
        self.inst.close()
