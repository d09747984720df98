import os
import sys

# the independent brute-force reference (tests/bruteforce.py) is imported as a plain module
sys.path.insert(0, os.path.dirname(__file__))
