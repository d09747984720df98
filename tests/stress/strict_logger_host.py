"""A host whose logger builds a string from the category (as OpenModelica's OMSimulator does with
std::string): a NULL category aborts the process (SIGABRT, exit status 134 in a shell). It runs one
FMI 2 co-simulation FMU through fmpy with debug logging off, sets one Real variable to a value the
model refuses, initialises (parameter) or steps and reads (input), and prints one JSON object: each
call's status, every message with its category, then frees the instance and instantiates a second
one that runs a step (the host survived the error). Usage:

    python tests/stress/strict_logger_host.py FMU_PATH NAME VALUE [LOGGING]

LOGGING ``on``: with debug logging on (pythonfmu's own wrapper logs an error only then).
"""
import ctypes
import json
import os
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.fmi2 import calloc, free

MESSAGES = []


def strict_logger(env, instance, status, category, message):
    if category is None:  # what std::string(nullptr) does
        sys.stdout.write(json.dumps({"aborted": "NULL category", "messages": MESSAGES}) + "\n")
        sys.stdout.flush()
        os.abort()
    MESSAGES.append([int(status), category.decode(), message.decode(errors="replace")])


def main(path, name, value, logging="off"):
    md = read_model_description(path)
    folder = extract(path)
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(strict_logger)
    callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    var = next(v for v in md.modelVariables if v.name == name)
    out = {"calls": {}}

    def call(label, fn):
        try:
            fn()
            out["calls"][label] = 0
        except Exception as exc:  # fmpy's FMICallException: the status
            out["calls"][label] = int(getattr(exc, "status", -1))

    fmu = FMU2Slave(guid=md.guid, unzipDirectory=folder, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="strict")
    fmu.instantiate(callbacks=callbacks, loggingOn=logging == "on")
    call("setReal", lambda: fmu.setReal([var.valueReference], [float(value)]))
    call("initialize", lambda: (fmu.setupExperiment(startTime=0.0), fmu.enterInitializationMode(),
                                fmu.exitInitializationMode()))
    if var.causality == "input":
        call("doStep", lambda: fmu.doStep(0.0, 0.01))
        out_vr = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
        call("getReal", lambda: fmu.getReal(out_vr[:1]))
    fmu.fmi2FreeInstance(fmu.component)
    # a second instance in the same process, with valid values: the host and the FMU go on
    again = FMU2Slave(guid=md.guid, unzipDirectory=folder, modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName="again")
    again.instantiate(callbacks=callbacks, loggingOn=False)
    again.setupExperiment(startTime=0.0)
    again.enterInitializationMode()
    again.exitInitializationMode()
    again.doStep(0.0, 0.01)
    again.terminate()
    again.freeInstance()
    out["messages"] = MESSAGES
    out["survived"] = True
    print(json.dumps(out))


if __name__ == "__main__":
    main(*sys.argv[1:5])
