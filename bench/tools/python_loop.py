"""Times napkin.transform over every test of a catalogue (bench/run_python.sh):
the inputs are read first (Catalogue.test_inputs), then transformed one after
another with the default config; prints the seconds the loop took."""

import sys
import time

import napkin

catalogue = napkin.Catalogue(sys.argv[1])
inputs = [catalogue.test_inputs(test_id) for test_id in catalogue.tests()]
start = time.perf_counter()
for test in inputs:
    napkin.transform(**test)
print("%.6f" % (time.perf_counter() - start))
