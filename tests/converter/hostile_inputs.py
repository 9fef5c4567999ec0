#!/usr/bin/env python3
"""hostile_inputs.py CONVERTER SOURCE_DIR CASE: apps/peridigm_to_prm.py (the
script CONVERTER, run with this Python) on one hostile input, CASE, in a new
scratch folder. Passes (exit status 0) only if

  - the exit status is the case's (1 for a refusal, 0 for what converts),
  - standard error has no Python traceback and matches the case's regex
    (a line 'Error: FILE...' naming the file, for a refusal),
  - every file that was in the folder before the run is byte-identical after
    it (the parameter file of a successful run excepted), and no temporary
    file is left,
  - the case's own check holds (e.g. a deck with a byte-order mark converts
    to the same parameter file as without it).

The run is bounded: 20 s and 1 GiB of address space (an unguarded read of
/dev/zero or a FIFO must fail the test, not the machine).
"""

import hashlib
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile

CONVERTER, SOURCE, CASE = sys.argv[1], sys.argv[2], sys.argv[3]
NODE_SET = ["--node-set", "top=expression:y > 0.45"]  # box_features.yaml's node set
TEXT_FILE_SETS = ["--node-set", "Node Set One=expression:x < 1e-4", "--node-set", "Node Set Two=expression:x > 3.9e-3"]


def source(name):
    return os.path.join(SOURCE, name)


def copy(name, to=None):
    shutil.copy(source(name), to or os.path.basename(name))


def write(name, data):
    with open(name, "wb") as f:
        f.write(data)


def read(name):
    with open(name, "rb") as f:
        return f.read()


def limit():
    resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))


def run(args, cwd="."):
    try:
        p = subprocess.run([sys.executable, CONVERTER] + args, cwd=cwd, capture_output=True, timeout=20,
                           preexec_fn=limit)
    except subprocess.TimeoutExpired:
        return None, "", "(timed out after 20 s)"
    return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")


def snapshot(folder="."):
    """{path: sha256} of every regular file under folder (links not followed)."""
    out = {}
    for base, dirs, files in os.walk(folder):
        for f in files:
            path = os.path.join(base, f)
            if os.path.isfile(path) and not os.path.islink(path):
                out[path] = hashlib.sha256(read(path)).hexdigest()
    return out


# Each case: set-up (returns the converter's arguments), expected exit status,
# a regex standard error must match (re.M), and an optional check after the run.
def overwrite_deck():
    copy("box_features.yaml", "deck.yaml")
    return ["-o", "deck.yaml", "deck.yaml"] + NODE_SET


def overwrite_deck_symlink():
    copy("box_features.yaml", "deck.yaml")
    os.symlink("deck.yaml", "link.prm")
    return ["-o", "link.prm", "deck.yaml"] + NODE_SET


def overwrite_deck_hardlink():
    copy("box_features.yaml", "deck.yaml")
    os.link("deck.yaml", "hard.prm")
    return ["-o", "hard.prm", "deck.yaml"] + NODE_SET


def overwrite_mesh():
    copy("exodus_tets.yaml")
    shutil.copy(os.path.join(SOURCE, "..", "physics", "box_tets.msh"), "box_tets.msh")
    return ["exodus_tets.yaml", "--mesh", "box_tets.msh", "--node-set", "left_end=expression:x<1", "-o", "box_tets.msh"]


def overwrite_point_file():
    copy("text_file.yaml")
    copy("wave_in_bar.txt")
    return ["text_file.yaml", "-o", "wave_in_bar.txt"] + TEXT_FILE_SETS


def replace_whole():
    copy("box_features.yaml", "deck.yaml")
    write("out.prm", b"old\n")
    os.chmod("out.prm", 0o640)
    os.link("out.prm", "keep.prm")  # the old file under another name
    return ["deck.yaml", "-o", "out.prm"] + NODE_SET


def check_replace_whole():
    # The new file replaced the old one by a rename: the old text is still
    # there under its other name, never written over in place; the mode kept.
    new = read("out.prm")
    ok = new.startswith(b"# PeriDeal parameter file converted from the Peridigm deck deck.yaml")
    ok &= read("keep.prm") == b"old\n" and (os.stat("out.prm").st_mode & 0o777) == 0o640
    return ok, "out.prm not replaced whole (by a rename, with mode 640), or keep.prm changed"


def failure_keeps_output():
    text = read(source("fragmenting_cylinder.yaml"))
    write("deck.yaml", re.sub(rb"Number Points Radius: *\d+", b"Number Points Radius: 0", text))
    write("out.prm", b"old\n")
    return ["deck.yaml", "-o", "out.prm"]


def binary():
    write("binary.yaml", bytes(range(256)) * 4)
    return ["binary.yaml"]


def same_as_utf8(name, encode):
    """The deck NAME in a/ as it is and in b/ re-encoded: both convert to the same text."""
    os.mkdir("a")
    os.mkdir("b")
    copy(name, os.path.join("a", "deck" + os.path.splitext(name)[1]))
    write(os.path.join("b", "deck" + os.path.splitext(name)[1]), encode(read(source(name)).decode("utf-8")))


def utf16_xml():
    same_as_utf8("fragmenting_cylinder.xml",
                 lambda t: ('<?xml version="1.0" encoding="UTF-16"?>' + t).encode("utf-16"))
    return ["deck.xml", "-o", "out.prm"]


def utf8_bom():
    same_as_utf8("box_features.yaml", lambda t: b"\xef\xbb\xbf" + t.encode("utf-8"))
    return ["deck.yaml", "-o", "out.prm"] + NODE_SET


def check_same_as_utf8():
    rc, _, err = run(CASES[CASE][0].args, cwd="a")
    ok = rc == 0 and os.path.exists("b/out.prm") and read("a/out.prm") == read("b/out.prm")
    return ok, "the re-encoded deck (b/) does not convert to the UTF-8 deck's (a/) parameter file"


def dev_zero():
    return ["/dev/zero"]


def fifo():
    os.mkfifo("deck.yaml")
    return ["deck.yaml"]


def missing_folder():
    copy("box_features.yaml", "deck.yaml")
    return ["deck.yaml", "-o", "no/such/out.prm"] + NODE_SET


def output_directory():
    copy("box_features.yaml", "deck.yaml")
    os.mkdir("out.prm")
    return ["deck.yaml", "-o", "out.prm"] + NODE_SET


def empty():
    write("empty.yaml", b"")
    return ["empty.yaml"]


def only_comments():
    write("comments.yaml", b"# a deck\n\n   # still nothing\n")
    return ["comments.yaml"]


def directory_deck():
    os.mkdir("deck.yaml")
    return ["deck.yaml"]


def huge():
    with open("huge.yaml", "wb") as f:
        f.truncate(20 << 20)  # sparse: instant, no disk
    return ["huge.yaml"]


def not_utf8():
    write("latin1.yaml", "Peridigm:\n  Discretization:\n    Type: \"PdQuickGrid\"\n    # Länge\n".encode("latin-1"))
    return ["latin1.yaml"]


def utf16_without_bom():
    write("le.yaml", read(source("box_features.yaml")).decode("utf-8").encode("utf-16-le"))
    return ["le.yaml"]


def peridigm_scalar():
    write("scalar.yaml", b"# one key\nPeridigm: 5\n")
    return ["scalar.yaml"]


def mesh_directory():
    copy("exodus_tets.yaml")
    os.mkdir("mesh.msh")
    return ["exodus_tets.yaml", "--mesh", "mesh.msh", "--node-set", "left_end=expression:x<1"]


def infinite_number():
    write("deck.yaml", read(source("box_features.yaml")).replace(b"X Length: 1.0", b"X Length: inf"))
    return ["deck.yaml"] + NODE_SET


def bad_node_set():
    copy("box_features.yaml", "deck.yaml")
    return ["deck.yaml", "--node-set", "top=box:1,2"]


def unknown_option():
    copy("box_features.yaml", "deck.yaml")
    return ["deck.yaml", "--no-such-option"]


class Case:
    def __init__(self, setup, status, regex, check=None):
        self.setup, self.status, self.regex, self.check = setup, status, regex, check
        self.args = None


CASES = {c[0].__name__: (Case(*c),) for c in [
    (overwrite_deck, 1, r"^Error: -o deck\.yaml is the deck deck\.yaml \(the same file\): the converter never "
                        r"overwrites a file it reads; nothing written"),
    (overwrite_deck_symlink, 1, r"^Error: -o link\.prm is the deck deck\.yaml \(the same file\)"),
    (overwrite_deck_hardlink, 1, r"^Error: -o hard\.prm is the deck deck\.yaml \(the same file\)"),
    (overwrite_mesh, 1, r"^Error: -o box_tets\.msh is the --mesh box_tets\.msh \(the same file\)"),
    (overwrite_point_file, 1, r"^Error: -o wave_in_bar\.txt is the deck's point file .*/wave_in_bar\.txt "
                              r"\(the same file\)"),
    (replace_whole, 0, r"\A(.*warning.*\n)*\Z", check_replace_whole),
    (failure_keeps_output, 1, r"^deck\.yaml:\d+: cannot convert '.*/Number Points Radius': must be at least 1, "
                              r"got 0\n(.*\n)*Error: 1 essential key"),
    (binary, 1, r"^Error: binary\.yaml:1: cannot read the deck: a NUL byte: a binary file, not a text deck$"),
    (utf16_xml, 0, r"", check_same_as_utf8),
    (utf8_bom, 0, r"", check_same_as_utf8),
    (dev_zero, 1, r"^Error: /dev/zero: cannot read the deck: it is a character device, not a regular file$"),
    (fifo, 1, r"^Error: deck\.yaml: cannot read the deck: it is a FIFO \(named pipe\), not a regular file$"),
    (missing_folder, 1, r"^Error: no/such/out\.prm: cannot write the parameter file: the folder no/such does not "
                        r"exist$"),
    (output_directory, 1, r"^Error: out\.prm: cannot write the parameter file: it is a directory, not a regular "
                          r"file$"),
    (empty, 1, r"^Error: empty\.yaml: cannot read the deck: the file is empty$"),
    (only_comments, 1, r"^comments\.yaml:1: syntax error: no section: the deck holds only comments\nError: "),
    (directory_deck, 1, r"^Error: deck\.yaml: cannot read the deck: it is a directory, not a regular file$"),
    (huge, 1, r"^Error: huge\.yaml: cannot read the deck: it is larger than 16 MiB"),
    (not_utf8, 1, r"^Error: latin1\.yaml:4: cannot read the deck: byte 0xe4 at column 8 is not UTF-8 text"),
    (utf16_without_bom, 1, r"^Error: le\.yaml:1: cannot read the deck: NUL bytes, as in UTF-16 text without a "
                           r"byte-order mark"),
    (peridigm_scalar, 1, r"^scalar\.yaml:2: syntax error: 'Peridigm' has a value"),
    (mesh_directory, 1, r"^Error: --mesh mesh\.msh: cannot read the mesh: it is a directory, not a regular file$"),
    (infinite_number, 1, r"^deck\.yaml:\d+: cannot convert '.*/X Length': 'inf' is not a finite number$"),
    (bad_node_set, 1, r"^Error: --node-set top=box:1,2: expected box:X0,Y0,Z0:X1,Y1,Z1$"),
    (unknown_option, 1, r"^Error: unrecognized arguments: --no-such-option$"),
]}


def main():
    case = CASES[CASE][0]
    scratch = tempfile.mkdtemp(prefix="converter_%s." % CASE, dir=os.getcwd())
    os.chdir(scratch)
    try:
        case.args = case.setup()
        before = snapshot()
        cwd = "b" if os.path.isdir("b") else "."
        rc, out, err = run(case.args, cwd=cwd)
        after = snapshot()
        failures = []
        if rc != case.status:
            failures.append("exit status %s, expected %d" % (rc, case.status))
        if "Traceback" in err:
            failures.append("a Python traceback")
        if not re.search(case.regex, err, re.M):
            failures.append("standard error does not match /%s/" % case.regex)
        written = os.path.join(cwd, "out.prm") if case.status == 0 else None
        for path, digest in before.items():
            if os.path.normpath(path) != os.path.normpath(written or "") and after.get(path) != digest:
                failures.append("%s changed or removed" % path)
        extra = [p for p in after if p not in before and os.path.normpath(p) != os.path.normpath(written or "")
                 and not p.startswith("./a/")]
        if extra:
            failures.append("files left: %s" % ", ".join(sorted(extra)))
        if case.check and not failures:
            ok, why = case.check()
            if not ok:
                failures.append(why)
        print("converter %s on the case %s: exit status %s" % (" ".join(case.args), CASE, rc))
        print("standard error:\n" + err)
        if failures:
            print("FAILED: " + "; ".join(failures))
            return 1
        print("passed")
        return 0
    finally:
        os.chdir("..")
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
