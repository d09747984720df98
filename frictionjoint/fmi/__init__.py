"""FMI 2.0 co-simulation adapters (pythonfmu slaves), FMU building and the fmpy master loop."""
