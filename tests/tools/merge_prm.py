#!/usr/bin/env python3
"""merge_prm.py [--source-dir DIR] BASE OVERLAY... : BASE with every 'set' of the OVERLAYs applied.

A test runs an example scene with a few settings changed (fewer steps, no
field files). pd_app refuses a key or a subsection given twice, so the
overlay is not appended: each of its 'set' lines replaces the base's value of
that key (or is added, with its subsections), as pd_study.py's --set does.
Prints the merged file, @PERIDEAL_SOURCE_DIR@ in it replaced by DIR (the
source tree). Run by tests/tools/run.sh (check --prm)."""
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


args = sys.argv[1:]
source_dir = None
if args[:1] == ["--source-dir"]:
    source_dir, args = args[1], args[2:]
if not args:
    sys.exit("usage: merge_prm.py [--source-dir DIR] BASE [OVERLAY...]")
with open(args[0]) as f:
    text = f.read()
for overlay in args[1:]:
    with open(overlay) as f:
        for a in assignments(f.read()):
            text = pd_study.override(text, a)
if source_dir is not None:
    text = text.replace("@PERIDEAL_SOURCE_DIR@", source_dir)
sys.stdout.write(text)
