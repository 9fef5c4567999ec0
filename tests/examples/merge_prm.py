#!/usr/bin/env python3
"""merge_prm.py BASE OVERLAY... : BASE with every 'set' of the OVERLAYs applied.

A test runs an example scene with a few settings changed (fewer steps, no
field files). pd_app refuses a key or a subsection given twice, so the
overlay is not appended: each of its 'set' lines replaces the base's value of
that key (or is added, with its subsections), as pd_study.py's --set does.
Prints the merged file."""
import importlib.util
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("pd_study", os.path.join(here, "..", "..", "apps", "pd_study.py"))
pd_study = importlib.util.module_from_spec(spec)
spec.loader.exec_module(pd_study)


def assignments(text):
    """'Sec/Sub/key=value' for every set line of a parameter file."""
    path, out = [], []
    for raw in text.split("\n"):
        s = raw.split("#")[0].strip()
        if s.startswith("subsection "):
            path.append(s[len("subsection "):].strip())
        elif s == "end":
            path.pop()
        elif s.startswith("set "):
            key, value = s[len("set "):].split("=", 1)
            out.append("/".join(path + [key.strip()]) + "=" + value.strip())
    return out


if len(sys.argv) < 2:
    sys.exit("usage: merge_prm.py BASE [OVERLAY...]")
with open(sys.argv[1]) as f:
    text = f.read()
for overlay in sys.argv[2:]:
    with open(overlay) as f:
        for a in assignments(f.read()):
            text = pd_study.override(text, a)
sys.stdout.write(text)
