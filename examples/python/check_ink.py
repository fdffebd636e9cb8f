#!/usr/bin/env python3
"""Runs examples/python/restitution_and_work.py into a scratch PNG and checks that the picture has
ink: a figure whose curves never drew is mostly white (ctest python_example_test).

    PYTHONPATH=build/python python3 examples/python/check_ink.py
"""

import os
import subprocess
import sys
import tempfile

import matplotlib.image
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

with tempfile.TemporaryDirectory() as folder:
    png = os.path.join(folder, "figure.png")
    subprocess.run([sys.executable, os.path.join(HERE, "restitution_and_work.py"), png],
                   check=True)
    pixels = matplotlib.image.imread(png)[..., :3]
    ink = np.mean(pixels.min(axis=-1) < 0.8)  # anything not near white
    coloured = np.mean(pixels.max(axis=-1) - pixels.min(axis=-1) > 0.2)  # the curves, not grey
    print("ink %.3f, coloured %.4f of the pixels" % (ink, coloured))
    # Axes, labels and three coloured curves on each panel: measured 0.05 ink, 0.01 coloured.
    if ink < 0.02 or coloured < 0.004:
        sys.exit("the figure is nearly blank")
