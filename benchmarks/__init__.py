"""Benchmarks of the source tree: the work-precision harness (harness.py) and the run-time scripts."""
