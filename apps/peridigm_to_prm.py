#!/usr/bin/env python3
"""peridigm_to_prm.py DECK [-o OUT.prm] [--partial] [options]: a Peridigm input
deck (YAML or Teuchos XML) as a PeriDeal parameter file.

  apps/peridigm_to_prm.py fragmenting_cylinder.yaml -o params.prm
  apps/peridigm_to_prm.py tensile_test.yaml --mesh dogbone.msh \\
      --node-set nodelist_1=box:-1,-1,-1:-0.046,1,1 -o params.prm

Without -o the parameter file goes to standard output. Every key or feature
that has no PeriDeal equivalent is named on standard error as

  DECK:LINE: cannot convert 'Section/Key': reason

(LINE is the deck's line of that key). If any of them matters for the
physics (geometry, material, damage, blocks, conditions, solver, contact) the
converter exits with status 1 and writes nothing, unless --partial is given,
in which case it writes what it could convert (still exiting with 1).
Features it converts only approximately are named as 'DECK:LINE: warning:
...' and do not change the exit status. Lines it could not convert that only
concern output (an output variable PeriDeal does not write, a compute class
it does not have) are reported but are not essential.

Files: the deck and --mesh must be regular files (checked before they are
opened: a FIFO, a device or a directory is refused by name), a deck at most
16 MiB of UTF-8 (a byte-order mark is skipped; UTF-16 with its byte-order mark
is decoded). -o is never a file the conversion reads (the same file under any
name included) and is written whole or not at all (a temporary file renamed
over it). Every such problem is one line 'Error: FILE[:LINE]: ...' and exit
status 1.

Options:
  --mesh FILE.msh        Peridigm's Exodus discretization is read from this
                         Gmsh mesh instead of the deck's Exodus mesh (which
                         pd_app reads itself without --mesh): Exodus
                         block_N is the Gmsh volume physical group N
                         (material id N). A mesh with tetrahedra, prisms or
                         pyramids is read with Cells as points = true (each
                         cell one point at its centroid, as Peridigm does).
  --node-set NAME=SPEC   what a Peridigm node set (an Exodus node set, a file
                         or list of point numbers) is in space, as a PeriDeal
                         region, instead of the mesh's node set or the
                         numbers (needed with --mesh and for cylinders): box:X0,Y0,Z0:X1,Y1,Z1, expression:EXPR (a
                         muparser expression in x, y, z, non-zero inside) or
                         group:N[:DIM] (a Gmsh physical group, DIM 3 or 2).
                         May be repeated.
  --seed N               Random seed of conditions whose value uses rnd()
                         (default 1, as doc/examples/fragmenting_cylinder).

Both formats are read without third-party modules: the YAML subset Peridigm
decks use (nested mappings by indentation, 'key: value', quoted strings,
comments) and Teuchos XML ParameterLists (with expat, for line numbers).
Peridigm's expressions (muParser in version 1.0, RTCompiler later: 'value =
...;', 'if (...) { ... } else { ... }', local variables) become PeriDeal's
muparser expressions ('if' becomes '?:'). doc/peridigm.md has the table of
what maps to what, and the traps.
"""

import argparse
import math
import os
import re
import stat
import sys
import tempfile
import xml.parsers.expat


# --------------------------------------------------------------- the deck tree


class DeckError(Exception):
    """A deck that cannot be read at all (syntax), at a line."""

    def __init__(self, line, message):
        super().__init__(message)
        self.line = line
        self.message = message


class Node:
    """A ParameterList (children is a dict, value None) or a Parameter (value a
    string). line: where its key stands in the deck."""

    def __init__(self, name, line, value=None, parent=None):
        self.name = name
        self.line = line
        self.value = value
        self.parent = parent
        self.children = None if value is not None else {}
        self.used = False

    def is_list(self):
        return self.children is not None

    def add(self, child):
        """child added under its name. A name given twice is Teuchos's rule:
        a parameter's last value stands (the earlier one is replaced, where it
        stood in the list), a list given twice is one list of both (a key in
        both: the later one); the root's 'duplicates' records each
        (earlier node, later node). A list and a value under one name, which
        Teuchos refuses, is a DeckError."""
        child.parent = self
        first = self.children.get(child.name)
        if first is None:
            self.children[child.name] = child
            return child
        if first.is_list() != child.is_list():
            where = re.sub(r"^Peridigm(/|$)", "", self.path())
            raise DeckError(child.line, "'%s' given twice in '%s', once as a list and once as a value (also "
                            "line %d)" % (child.name, where or "the top level", first.line))
        root = self
        while root.parent is not None:
            root = root.parent
        root.__dict__.setdefault("duplicates", []).append((first, child))
        if child.is_list():
            return first  # its entries go into the first list
        self.children[child.name] = child
        return child

    def path(self):
        parts = []
        node = self
        while node is not None and node.parent is not None:
            parts.append(node.name)
            node = node.parent
        return "/".join(reversed(parts))

    def last_line(self):
        last = max(self.line, getattr(self, "end_line", 0))
        if self.children:
            for c in self.children.values():
                last = max(last, c.last_line())
        return last


def _strip_yaml_comment(s):
    """s without a trailing ' # comment' (outside quotes)."""
    quote = None
    i = 0
    while i < len(s):
        c = s[i]
        if quote == '"':
            if c == "\\":
                i += 1
            elif c == '"':
                quote = None
        elif quote == "'":
            if c == "'":
                quote = None
        elif c in "\"'" and (i == 0 or s[i - 1] in " :\t"):
            quote = c
        elif c == "#" and (i == 0 or s[i - 1] in " \t"):
            return s[:i].rstrip()
        i += 1
    return s.rstrip()


def _yaml_double_quoted(s, line):
    """The string of a double-quoted YAML scalar s (starting with '"') and the
    text after its closing quote."""
    out = []
    i = 1
    while i < len(s):
        c = s[i]
        if c == "\\":
            if i + 1 >= len(s):
                break
            e = s[i + 1]
            out.append({"n": "\n", "t": "\t", '"': '"', "\\": "\\", "/": "/"}.get(e, e))
            i += 2
            continue
        if c == '"':
            return "".join(out), s[i + 1:]
        out.append(c)
        i += 1
    raise DeckError(line, "a string opened with \" is not closed on its line")


def _yaml_single_quoted(s, line):
    out = []
    i = 1
    while i < len(s):
        if s[i] == "'":
            if i + 1 < len(s) and s[i + 1] == "'":
                out.append("'")
                i += 2
                continue
            return "".join(out), s[i + 1:]
        out.append(s[i])
        i += 1
    raise DeckError(line, "a string opened with ' is not closed on its line")


def _yaml_scalar(text, line):
    text = text.strip()
    if text.startswith('"'):
        value, rest = _yaml_double_quoted(text, line)
    elif text.startswith("'"):
        value, rest = _yaml_single_quoted(text, line)
    else:
        if text[:1] in ("[", "{", "&", "*", "|", ">", "!", "%", "@", "`"):
            raise DeckError(line, "YAML '%s' (flow collections, anchors, block scalars, tags) "
                            "is not in the subset Peridigm decks use" % text[:1])
        return text
    if rest.strip():
        raise DeckError(line, "text after the closing quote: '%s'" % rest.strip())
    return value


def parse_yaml(text):
    """The deck's tree. Nested mappings by indentation (spaces), 'key: value'
    and 'key:' lines, quoted or plain scalars, '#' comments."""
    root = Node("", 0)
    stack = [(-1, root)]  # open mappings: (indentation of their key, node)
    child_indent = {id(root): None}
    for number, raw in enumerate(text.split("\n"), 1):
        raw = raw.rstrip("\r")
        if not raw.strip() or raw.lstrip().startswith("#"):
            continue
        body = raw.lstrip(" ")
        indent = len(raw) - len(body)
        if body.startswith("\t"):
            raise DeckError(number, "indentation by a tab (YAML indents with spaces)")
        body = _strip_yaml_comment(body)
        if body in ("---", "..."):
            continue
        if body.startswith("- ") or body == "-":
            raise DeckError(number, "a YAML sequence ('- item'): Peridigm decks are mappings only")
        # The key: quoted, or plain up to the first ': ' or a final ':'.
        if body[0] in "\"'":
            key, after = (_yaml_double_quoted if body[0] == '"' else _yaml_single_quoted)(body, number)
            if not after.startswith(":"):
                raise DeckError(number, "no ':' after the key %s" % body[: len(key) + 2])
            rest = after[1:]
        else:
            m = re.search(r":(\s|$)", body)
            if not m:
                raise DeckError(number, "no 'key: value' on this line: '%s'" % body)
            key, rest = body[: m.start()].strip(), body[m.start() + 1:]
        if not key:
            raise DeckError(number, "an empty key")
        while stack[-1][0] >= indent:
            stack.pop()
        parent = stack[-1][1]
        expected = child_indent[id(parent)]
        if expected is None:
            child_indent[id(parent)] = indent
        elif expected != indent:
            last = list(parent.children.values())[-1] if parent.children else None
            if indent > expected and last is not None and not last.is_list():
                raise DeckError(number, "'%s' (line %d) has a value, so it cannot have entries"
                                % (last.name, last.line))
            raise DeckError(number, "indented by %d spaces where the entries of '%s' are indented by %d"
                            % (indent, re.sub(r"^Peridigm(/|$)", "", parent.path()) or "the top level",
                               expected))
        if rest.strip():
            node = Node(key, number, _yaml_scalar(rest, number))
            parent.add(node)
        else:
            node = parent.add(Node(key, number))
            stack.append((indent, node))
            child_indent.setdefault(id(node), None)
    return root


def parse_xml(text):
    """The deck's tree from Teuchos XML: <ParameterList name="..."> and
    <Parameter name="..." type="..." value="..."/>, with expat's line numbers."""
    parser = xml.parsers.expat.ParserCreate()
    root = Node("", 0)
    stack = []
    state = {"seen_root": False}

    def start(tag, attrs):
        line = parser.CurrentLineNumber
        if stack and not stack[-1].is_list():
            raise DeckError(line, "<%s> inside a <Parameter>" % tag)
        if tag == "ParameterList":
            if not stack:
                if state["seen_root"]:
                    raise DeckError(line, "a second top-level <ParameterList>")
                state["seen_root"] = True
                root.line = line
                stack.append(root)
                return
            if "name" not in attrs:
                raise DeckError(line, "a <ParameterList> without a name")
            node = stack[-1].add(Node(attrs["name"], line))
            stack.append(node)
        elif tag == "Parameter":
            if not stack:
                raise DeckError(line, "a <Parameter> outside every <ParameterList>")
            for a in ("name", "value"):
                if a not in attrs:
                    raise DeckError(line, "a <Parameter> without '%s'" % a)
            node = Node(attrs["name"], line, attrs["value"])
            node.xml_type = attrs.get("type", "")
            stack[-1].add(node)
            stack.append(node)
        else:
            raise DeckError(line, "<%s>: a Peridigm XML deck holds only <ParameterList> and <Parameter>" % tag)

    def end(tag):
        stack.pop().end_line = parser.CurrentLineNumber

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        parser.Parse(text, True)
    except xml.parsers.expat.ExpatError as e:
        raise DeckError(e.lineno, "XML: %s" % xml.parsers.expat.ErrorString(e.code))
    if not state["seen_root"]:
        raise DeckError(1, "no <ParameterList>")
    return root


# ---------------------------------------------------------------- the files
#
# Every file the converter opens goes through open_regular(): os.stat first,
# so a FIFO, a device (/dev/zero), a directory or a socket is refused by name
# before it is opened (a FIFO would block the open, /dev/zero never ends);
# then opened without blocking and checked again on the open descriptor (the
# path may have changed in between). read_text() adds the size limit and the
# decoding; a problem is an InputError whose message names the file (and the
# line where there is one).

MAX_DECK_BYTES = 16 << 20  # a Peridigm deck is a few kB; beyond this it is not one

UTF8_BOM = b"\xef\xbb\xbf"
UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")
UTF32_BOMS = (b"\xff\xfe\x00\x00", b"\x00\x00\xfe\xff")


class InputError(Exception):
    """A file the converter cannot use; the message names it (and the line)."""


def _file_kind(mode):
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def regular_file_problem(path):
    """Why PATH cannot be read as a file ('no such file', 'a directory', ...),
    or None if it is a regular file. Never opens it."""
    try:
        st = os.stat(path)
    except OSError as e:
        return e.strerror.lower() if e.strerror else str(e)
    if not stat.S_ISREG(st.st_mode):
        return "it is %s, not a regular file" % _file_kind(st.st_mode)
    return None


def open_regular(path, what):
    """PATH opened for reading in binary mode, if it is a regular file.
    WHAT names it in messages ('the deck', '--mesh')."""
    problem = regular_file_problem(path)
    if problem:
        raise InputError("%s: cannot read %s: %s" % (path, what, problem))
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as e:
        raise InputError("%s: cannot read %s: %s" % (path, what, e.strerror))
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise InputError("%s: cannot read %s: it is not a regular file" % (path, what))
    return os.fdopen(fd, "rb")


def decode_text(data, path, what):
    """The text of DATA, a file's bytes: UTF-8 (a byte-order mark is skipped),
    or UTF-16 with its byte-order mark (decoded). Anything else (UTF-32, a NUL
    byte, bytes that are not UTF-8) is an InputError naming the line."""
    if data.startswith(UTF32_BOMS):
        raise InputError("%s: cannot read %s: it is UTF-32 text (byte-order mark); save it as UTF-8" % (path, what))
    if data.startswith(UTF16_BOMS):
        try:
            return data.decode("utf-16")
        except UnicodeDecodeError as e:
            line = data[:e.start].decode("utf-16", "replace").count("\n") + 1
            raise InputError("%s:%d: cannot read %s: it starts with a UTF-16 byte-order mark but is not "
                             "valid UTF-16 (%s); save it as UTF-8" % (path, line, what, e.reason))
    if data.startswith(UTF8_BOM):
        data = data[len(UTF8_BOM):]
    nul = data.find(b"\x00")
    if nul >= 0:
        line = data[:nul].count(b"\n") + 1
        odd, even = data[1::2], data[0::2]
        if any(a.count(0) >= 0.9 * len(a) and b.count(0) <= 0.05 * len(b) for a, b in ((odd, even), (even, odd))):
            raise InputError("%s:%d: cannot read %s: NUL bytes, as in UTF-16 text without a byte-order mark; "
                             "save it as UTF-8" % (path, line, what))
        raise InputError("%s:%d: cannot read %s: a NUL byte: a binary file, not a text deck" % (path, line, what))
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data[:e.start].count(b"\n") + 1
        column = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise InputError("%s:%d: cannot read %s: byte 0x%02x at column %d is not UTF-8 text; save the file as "
                         "UTF-8" % (path, line, what, data[e.start], column))


def read_text(path, what, limit=MAX_DECK_BYTES):
    """The text of the regular file PATH (open_regular, decode_text), at most
    LIMIT bytes; an empty file is an InputError too."""
    with open_regular(path, what) as f:
        try:
            data = f.read(limit + 1)
        except OSError as e:
            raise InputError("%s: cannot read %s: %s" % (path, what, e.strerror))
    if len(data) > limit:
        raise InputError("%s: cannot read %s: it is larger than %d MiB, which no Peridigm deck is"
                         % (path, what, limit >> 20))
    text = decode_text(data, path, what)
    if not text.strip():
        raise InputError("%s: cannot read %s: the file is empty" % (path, what))
    return text


def read_deck(path):
    text = read_text(path, "the deck")
    if text.lstrip().startswith("<"):
        root = parse_xml(text)
    else:
        root = parse_yaml(text)
        # Peridigm's YAML decks hang everything under 'Peridigm:'.
        if len(root.children) == 1:
            (only,) = root.children.values()
            if only.name == "Peridigm" and not only.is_list():
                raise DeckError(only.line, "'Peridigm' has a value; the deck's sections (Discretization, "
                                "Materials, ...) belong under it")
            if only.is_list() and only.name == "Peridigm":
                only.parent = None
                only.duplicates = getattr(root, "duplicates", [])
                return only
    if not root.children:
        raise DeckError(max(root.line, 1), "no section: the deck holds only comments")
    root.parent = None
    return root


# ------------------------------------------------------------- the .prm output


class Prm:
    """A subsection of the parameter file: comments, set lines, subsections."""

    def __init__(self, name=None):
        self.name = name
        self.items = []

    def comment(self, text):
        for line in text.split("\n"):
            self.items.append(("comment", line))

    def set(self, key, value, comment=None):
        """Set key (again: its value changes in place); new keys go before the
        first subsection, with their comment lines."""
        for at, item in enumerate(self.items):
            if item[0] == "set" and item[1] == key:
                item[2] = value
                if comment:
                    self.items[at:at] = [("comment", line) for line in comment.split("\n")]
                return
        at = next((i for i, item in enumerate(self.items) if item[0] == "sub"), len(self.items))
        new = [("comment", line) for line in comment.split("\n")] if comment else []
        self.items[at:at] = new + [["set", key, value]]

    def sub(self, name):
        for item in self.items:
            if item[0] == "sub" and item[1].name == name:
                return item[1]
        s = Prm(name)
        self.items.append(("sub", s))
        return s

    def render(self, depth=0):
        pad = "  " * depth
        out = []
        width = max([len(i[1]) for i in self.items if i[0] == "set"] or [0])
        for item in self.items:
            if item[0] == "comment":
                out.append((pad + "# " + item[1]).rstrip() if item[1] else pad + "#")
            elif item[0] == "set":
                out.append(("%sset %-*s = %s" % (pad, width, item[1], item[2])).rstrip())
            else:
                out.append("%ssubsection %s" % (pad, item[1].name))
                out.extend(item[1].render(depth + 1))
                out.append("%send" % pad)
        return out


# ------------------------------------------------------------ the expressions

_FUNCTIONS = {
    # Peridigm (C library / RTCompiler / muParser) -> PeriDeal's muparser.
    "sin": "sin", "cos": "cos", "tan": "tan", "asin": "asin", "acos": "acos", "atan": "atan",
    "atan2": "atan2", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "exp": "exp",
    "sqrt": "sqrt", "abs": "abs", "fabs": "abs", "pow": "pow", "floor": "floor", "ceil": "ceil",
    "min": "min", "max": "max", "rnd": "rnd", "log10": "log10", "sign": "sign",
    # C's and RTCompiler's log is the natural logarithm; muparser's log is
    # base 10 and its natural logarithm is ln.
    "log": "ln", "ln": "ln",
}

_TOKEN = re.compile(r"\s*(?:(\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?)|([A-Za-z_]\w*)|"
                    r"(==|!=|<=|>=|&&|\|\||[-+*/^(),;{}=<>!?:%]))")


class ExprError(Exception):
    pass


def _tokens(text):
    text = text.replace("\\{", "{").replace("\\}", "}")
    out = []
    pos = 0
    text = text.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise ExprError("cannot read '%s'" % text[pos:].strip()[:20])
        if m.group(1):
            out.append(("num", m.group(1)))
        elif m.group(2):
            out.append(("id", m.group(2)))
        else:
            out.append(("op", m.group(3)))
        pos = m.end()
    return out


def translate_expression(text, variables=("x", "y", "z", "t")):
    """A Peridigm function string (muParser or RTCompiler) as a muparser
    expression in the given variables. Raises ExprError."""
    tokens = _tokens(text)
    if not tokens:
        raise ExprError("empty")
    has_statements = any(t == ("op", ";") or t == ("op", "=") or t == ("id", "if") for t in tokens)

    def expr_text(toks, env):
        out = []
        for i, (kind, tok) in enumerate(toks):
            nxt = toks[i + 1] if i + 1 < len(toks) else None
            if kind == "id":
                if nxt == ("op", "("):
                    if tok not in _FUNCTIONS:
                        raise ExprError("function '%s' has no muparser equivalent here" % tok)
                    out.append(_FUNCTIONS[tok])
                elif tok in env:
                    if env[tok] is None:
                        raise ExprError("'%s' is used before it is set" % tok)
                    out.append("(" + env[tok] + ")")
                elif tok in variables:
                    out.append(tok)
                else:
                    raise ExprError("unknown name '%s' (PeriDeal's expressions know %s)"
                                    % (tok, ", ".join(variables)))
            elif kind == "op" and tok in ("!", "%", "{", "}", ";", "="):
                raise ExprError("'%s' has no muparser equivalent" % tok)
            else:
                out.append(tok)
        s = ""
        for tok in out:
            # Two words or numbers in a row keep a space between them.
            if s and (s[-1].isalnum() or s[-1] in "_.") and (tok[0].isalnum() or tok[0] in "_."):
                s += " "
            s += tok
        return s

    if not has_statements:
        return expr_text(tokens, {})

    # RTCompiler statements: [double] NAME = expr; if (cond) {..} else {..}
    pos = [0]

    def peek():
        return tokens[pos[0]] if pos[0] < len(tokens) else None

    def take(expected=None):
        tok = peek()
        if tok is None or (expected is not None and tok != expected):
            raise ExprError("expected '%s'" % (expected[1] if expected else "more"))
        pos[0] += 1
        return tok

    def until_statement_end():
        start = pos[0]
        depth = 0
        while pos[0] < len(tokens):
            tok = tokens[pos[0]]
            if tok == ("op", "("):
                depth += 1
            elif tok == ("op", ")"):
                depth -= 1
            elif depth == 0 and tok in (("op", ";"), ("op", "}")):
                break
            pos[0] += 1
        return tokens[start:pos[0]]

    def condition():
        take(("op", "("))
        start = pos[0]
        depth = 1
        while True:
            tok = take()
            if tok == ("op", "("):
                depth += 1
            elif tok == ("op", ")"):
                depth -= 1
                if depth == 0:
                    return tokens[start:pos[0] - 1]

    def block(env):
        if peek() == ("op", "{"):
            take()
            while peek() != ("op", "}"):
                if peek() is None:
                    raise ExprError("'{' not closed")
                statement(env)
            take()
        else:
            statement(env)

    def statement(env):
        tok = peek()
        if tok == ("op", ";"):
            take()
            return
        if tok == ("id", "if"):
            take()
            cond = expr_text(condition(), env)
            then_env = dict(env)
            block(then_env)
            else_env = dict(env)
            if peek() == ("id", "else"):
                take()
                block(else_env)
            for name in set(then_env) | set(else_env):
                a, b = then_env.get(name), else_env.get(name)
                if a == b:
                    env[name] = a
                elif a is None or b is None:
                    raise ExprError("'%s' is set on one branch of an if only" % name)
                else:
                    env[name] = "(%s) ? (%s) : (%s)" % (cond, a, b)
            return
        if tok in (("id", "double"), ("id", "float"), ("id", "int")):
            take()
            tok = peek()
        if tok is None or tok[0] != "id":
            raise ExprError("expected a statement")
        name = take()[1]
        if name in variables:
            raise ExprError("assigns to the variable '%s'" % name)
        take(("op", "="))
        env[name] = expr_text(until_statement_end(), env)
        if not env[name]:
            raise ExprError("'%s = ' without a value" % name)
        if peek() == ("op", ";"):
            take()

    env = {"value": "0"}
    while peek() is not None:
        statement(env)
    return env["value"]


_EVAL_FUNCTIONS = {
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin, "acos": math.acos, "atan": math.atan,
    "atan2": math.atan2, "sinh": math.sinh, "cosh": math.cosh, "tanh": math.tanh, "exp": math.exp,
    "sqrt": math.sqrt, "abs": abs, "pow": math.pow, "floor": math.floor, "ceil": math.ceil, "min": min,
    "max": max, "log10": math.log10, "ln": math.log, "sign": lambda v: (v > 0) - (v < 0),
}


def evaluate_expression(text, values):
    """The value of a muparser expression as translate_expression writes it
    (numbers, the variables in VALUES, the functions of _FUNCTIONS but rnd,
    + - * / ^, comparisons, && ||, ?:). Raises ExprError for what it cannot
    evaluate (rnd, a math error)."""
    tokens = _tokens(text)
    pos = [0]

    def peek():
        return tokens[pos[0]] if pos[0] < len(tokens) else (None, None)

    def take():
        pos[0] += 1
        return tokens[pos[0] - 1]

    def expect(op):
        if peek() != ("op", op):
            raise ExprError("expected '%s'" % op)
        take()

    def ternary():
        c = logical_or()
        if peek() == ("op", "?"):
            take()
            a = ternary()
            expect(":")
            b = ternary()
            return a if c != 0 else b
        return c

    def binary(level):
        ops = (("||",), ("&&",), ("==", "!="), ("<", ">", "<=", ">="), ("+", "-"), ("*", "/"))
        if level == len(ops):
            return unary()
        v = binary(level + 1)
        while peek()[0] == "op" and peek()[1] in ops[level]:
            op = take()[1]
            w = binary(level + 1)
            v = {"||": lambda: float(v != 0 or w != 0), "&&": lambda: float(v != 0 and w != 0),
                 "==": lambda: float(v == w), "!=": lambda: float(v != w), "<": lambda: float(v < w),
                 ">": lambda: float(v > w), "<=": lambda: float(v <= w), ">=": lambda: float(v >= w),
                 "+": lambda: v + w, "-": lambda: v - w, "*": lambda: v * w, "/": lambda: v / w}[op]()
        return v

    def logical_or():
        return binary(0)

    def unary():
        if peek() == ("op", "-"):
            take()
            return -unary()
        if peek() == ("op", "+"):
            take()
            return unary()
        return power()

    def power():
        v = primary()
        if peek() == ("op", "^"):
            take()
            return v ** unary()
        return v

    def primary():
        kind, tok = take() if pos[0] < len(tokens) else (None, None)
        if kind == "num":
            return float(tok)
        if kind == "id":
            if peek() == ("op", "("):
                if tok not in _EVAL_FUNCTIONS:
                    raise ExprError("'%s' cannot be evaluated here" % tok)
                take()
                args = [ternary()]
                while peek() == ("op", ","):
                    take()
                    args.append(ternary())
                expect(")")
                return float(_EVAL_FUNCTIONS[tok](*args))
            if tok in values:
                return float(values[tok])
            raise ExprError("unknown name '%s'" % tok)
        if (kind, tok) == ("op", "("):
            v = ternary()
            expect(")")
            return v
        raise ExprError("unexpected '%s'" % tok)

    try:
        v = ternary()
    except (ArithmeticError, ValueError, TypeError) as e:
        raise ExprError(str(e))
    if pos[0] != len(tokens):
        raise ExprError("unexpected '%s'" % tokens[pos[0]][1])
    return v


# ------------------------------------------------------------- the conversion


def is_number(s):
    """True for a finite number: 'inf' and 'nan' are no value of a deck."""
    try:
        return math.isfinite(float(s))
    except (TypeError, ValueError):
        return False


def fmt(v):
    """A float as the shortest text that reads back the same."""
    if float(v) == int(v) and abs(v) < 1e15:
        return str(int(v))
    return repr(float(v))


def num(s):
    """A deck number as written, tidied (a Teuchos double '7800.0' stays)."""
    return s.strip()


def gmsh_volume_cells(path):
    """(text, ids) of the Gmsh mesh PATH (ASCII, format 2.2 or 4.1): text names
    its 3D cells that are not hexahedra ('200 tetrahedra', '' if none), ids is
    the set of the physical groups of its 3D cells (pd_app's material ids: the
    first physical tag, 0 for none). ('', None) if the file cannot be read
    (pd_app then says why)."""
    names = {4: "tetrahedron", 6: "prism", 7: "pyramid", 11: "tetrahedron", 13: "prism", 14: "pyramid"}
    volume_types = {4, 5, 6, 7, 11, 12, 13, 14, 17, 18, 19}
    plural = {"tetrahedron": "tetrahedra", "prism": "prisms", "pyramid": "pyramids"}
    counts = {}
    ids = set()
    try:
        with open_regular(path, "--mesh") as f:
            lines = iter([line.decode("utf-8", "replace") for line in f])
        version = None
        physical = {}  # format 4.1: volume entity tag -> its physical group
        for line in lines:
            if line.strip() == "$MeshFormat":
                version = next(lines).split()[0]
            elif line.strip() == "$Entities":
                n = [int(v) for v in next(lines).split()[:4]]
                for d in range(4):
                    for _ in range(n[d]):
                        t = next(lines).split()
                        if d == 3:
                            physical[int(t[0])] = int(t[8]) if int(t[7]) > 0 else 0
            elif line.strip() == "$Elements":
                if version is not None and version.startswith("4"):
                    n_blocks = int(next(lines).split()[0])
                    for _ in range(n_blocks):
                        dim, tag, kind, n = (int(v) for v in next(lines).split()[:4])
                        for _ in range(n):
                            next(lines)
                        if kind in names:
                            counts[names[kind]] = counts.get(names[kind], 0) + n
                        if dim == 3 and kind in volume_types and n > 0:
                            ids.add(physical.get(tag, 0))
                else:
                    for _ in range(int(next(lines).split()[0])):
                        t = next(lines).split()
                        kind = int(t[1])
                        if kind in names:
                            counts[names[kind]] = counts.get(names[kind], 0) + 1
                        if kind in volume_types:
                            ids.add(int(t[3]) if int(t[2]) > 0 else 0)
                break
    except (InputError, OSError, ValueError, IndexError, StopIteration):
        return "", None
    text = " and ".join("%d %s" % (n, name if n == 1 else plural[name]) for name, n in sorted(counts.items()))
    return text, ids


def cells_other_than_hexahedra(path):
    """The 3D cells of the Gmsh mesh PATH that are not hexahedra, as text
    ('200 tetrahedra'); '' if none or unreadable."""
    return gmsh_volume_cells(path)[0]


def text_file_blocks(path):
    """The block numbers of Peridigm's Text File PATH (x y z block volume per
    line, '#' comments), or None if it cannot be read."""
    ids = set()
    try:
        with open_regular(path, "the point file") as f:
            for raw in f:
                t = raw.decode("utf-8", "replace").split("#")[0].split()
                if len(t) >= 5:
                    ids.add(int(float(t[3])))
    except (InputError, OSError, ValueError):
        return None
    return ids


def exodus_pieces(path):
    """The files of the Exodus mesh PATH: [PATH], or the pieces PATH.N.i of
    its decomposition (the smallest complete N) if PATH does not exist, as
    pd_app reads them; [] if there are none."""
    if os.path.lexists(path):
        return [path]
    folder = os.path.dirname(path) or "."
    base = os.path.basename(path)
    found = {}
    try:
        names = os.listdir(folder)
    except OSError:
        return []
    for name in names:
        m = re.fullmatch(re.escape(base) + r"\.(\d{1,9})\.(\d{1,9})", name)
        if m:
            found.setdefault(int(m.group(1)), {})[int(m.group(2))] = os.path.join(folder, name)
    for n in sorted(found):
        if n > 0 and sorted(found[n]) == list(range(n)):
            return [found[n][i] for i in range(n)]
    return []


class ExodusNames:
    """The element blocks {name: id} and node sets {name} of an Exodus mesh,
    named as Peridigm names them (block_ID, nodelist_ID where the file gives
    no name), read with python3-netcdf4. error says why they could not be
    read (then the dictionaries are empty)."""

    def __init__(self, path):
        self.blocks, self.node_sets, self.error = {}, set(), None
        pieces = exodus_pieces(path)
        if not pieces:
            self.error = "neither '%s' nor the pieces '%s.N.i' of a decomposition exist" % (path, path)
            return
        try:
            import netCDF4
        except ImportError:
            self.error = "reading an Exodus mesh needs python3-netcdf4 (Debian's package; ./setup.sh installs it)"
            return
        try:
            for piece in pieces:
                problem = regular_file_problem(piece)
                if problem:
                    raise InputError("'%s': %s" % (piece, problem))
                with netCDF4.Dataset(piece) as d:
                    self.blocks.update(self.named(d, "eb_prop1", "eb_names", "block_"))
                    self.node_sets.update(self.named(d, "ns_prop1", "ns_names", "nodelist_"))
        except (InputError, OSError, RuntimeError, KeyError, ValueError) as e:
            self.error = "'%s' cannot be read as an Exodus II mesh (%s)" % (path, e)
            self.blocks, self.node_sets = {}, set()

    @staticmethod
    def named(d, ids, names, prefix):
        import netCDF4
        if ids not in d.variables:
            return {}
        numbers = [int(i) for i in d.variables[ids][:]]
        texts = [""] * len(numbers)
        if names in d.variables:
            texts = [str(t).strip() for t in netCDF4.chartostring(d.variables[names][:])]
        return {(t or "%s%d" % (prefix, i)): i for i, t in zip(numbers, texts)}


class Converter:
    ESSENTIAL_SECTIONS = ("Discretization", "Materials", "Blocks", "Solver")

    def __init__(self, deck_path, root, args):
        self.deck = deck_path
        self.root = root
        self.args = args
        self.messages = []  # (line, order, text, essential)
        self.essential_failures = 0
        self.prm = Prm()
        self.sections = {}
        self.disc_type = None  # Box, Cylinder shell, Gmsh
        self.block_map = {}  # Peridigm discretization block name -> PeriDeal block name
        self.block_ids = {}  # Peridigm discretization block name -> Gmsh material id
        self.regions = {}  # PeriDeal region name -> (type, dict)
        self.region_order = []
        self.node_set_defs = {}  # node sets defined in Boundary Conditions: name -> node
        self.node_set_specs = {}
        self.labels = set()  # compute output labels (globals CSV columns)
        self.materials = {}
        self.damage_models = {}
        self.hourglass = {}  # material -> (Peridigm's Hourglass Coefficient, its node, the .prm subsection)
        # The files the conversion reads or names as input: never its output.
        self.input_files = [("the deck", deck_path), ("the --mesh", args.mesh)]
        for spec in args.node_set or []:
            if "=" not in spec:
                raise InputError("--node-set %s: expected NAME=SPEC" % spec)
            name, what = spec.split("=", 1)
            self.node_set_specs[name.strip()] = what.strip()

    # --- messages

    def _line(self, node):
        return node.line if node is not None else 0

    def cannot(self, node, reason, essential=True, path=None):
        path = path or (node.path() if node is not None else "")
        self.messages.append((self._line(node), len(self.messages),
                              "%s:%d: cannot convert '%s': %s" % (self.deck, self._line(node), path, reason),
                              essential))
        if essential:
            self.essential_failures += 1

    def warn(self, node, reason, path=None):
        path = path or node.path()
        self.messages.append((self._line(node), len(self.messages),
                              "%s:%d: warning: '%s': %s" % (self.deck, self._line(node), path, reason), False))

    def lines(self, node):
        a, b = node.line, node.last_line()
        return "line %d" % a if a == b else "lines %d-%d" % (a, b)

    def from_comment(self, section, node, what=None):
        section.comment("From %s, %s%s." % (os.path.basename(self.deck), self.lines(node),
                                            " (" + what + ")" if what else " ('%s')" % node.path()))

    # --- reading keys

    def child(self, node, key):
        if node is None or not node.is_list():
            return None
        c = node.children.get(key)
        if c is not None:
            c.used = True
        return c

    def text(self, node, key, required=False, essential=True):
        c = self.child(node, key)
        if c is None:
            if required:
                self.cannot(node, "'%s' is missing" % key, essential, path=node.path() + "/" + key)
            return None
        if c.is_list():
            self.cannot(c, "a value was expected, not a list", essential)
            return None
        if "#" in c.value or "\n" in c.value:
            self.cannot(c, "a value with '#' or a line break: a PeriDeal parameter file reads '#' as the "
                        "start of a comment", essential)
            return None
        return c.value.strip()

    def bad_name(self, node, essential=True):
        """True (and reported) if node's name cannot be a PeriDeal entry name."""
        if any(ch in node.name for ch in ",#\n") or not node.name.strip():
            self.cannot(node, "the name '%s' cannot be a PeriDeal entry name (no commas, no '#': the names "
                        "are a comma separated list)" % node.name, essential)
            self.skip(node)
            return True
        return False

    def list_entries(self, section, what, essential=True):
        """The named lists of section, each marked read; entries with a bad name or
        that are not lists are reported ('what' says what an entry should be)."""
        for c in section.children.values():
            c.used = True
            if self.bad_name(c, essential):
                continue
            if not c.is_list():
                self.cannot(c, what, essential)
                continue
            yield c

    def number(self, node, key, required=False, essential=True, integer=False):
        c = self.child(node, key)
        if c is None:
            if required:
                self.cannot(node, "'%s' is missing" % key, essential, path=node.path() + "/" + key)
            return None
        if c.is_list() or not is_number(c.value) or (integer and not re.fullmatch(r"\s*[-+]?\d+\s*", c.value)):
            self.cannot(c, "'%s' is not %s" % (c.value if not c.is_list() else "a list",
                                               "an integer" if integer else "a finite number"), essential)
            return None
        return c.value.strip()

    def boolean(self, node, key):
        c = self.child(node, key)
        if c is None:
            return None
        v = (c.value or "").strip().lower()
        if v in ("true", "yes", "on", "1"):
            return True
        if v in ("false", "no", "off", "0"):
            return False
        self.cannot(c, "'%s' is not true or false" % c.value)
        return None

    def skip(self, node):
        """Mark node and everything in it read: a part reported as a whole."""
        node.used = True
        for c in (node.children or {}).values():
            self.skip(c)

    def leftovers(self, node, essential=True, reason=None):
        """Every child not read: no PeriDeal equivalent known."""
        if node is None or not node.is_list():
            return
        for c in node.children.values():
            if not c.used:
                c.used = True
                self.cannot(c, reason or "a key the converter does not know (no PeriDeal equivalent)", essential)

    # --- the sections

    def run(self):
        top = self.root
        # Decks before Peridigm 1.0 wrapped the problem in 'Problem'.
        problem = top.children.get("Problem")
        if problem is not None and problem.is_list():
            problem.used = True
            for c in list(problem.children.values()):
                if c.name in top.children:
                    self.cannot(c, "given both in Problem and at the top level")
                    continue
                top.children[c.name] = c
                c.parent = top
        verbose = self.child(top, "Verbose")
        for first, last in getattr(top, "duplicates", []):
            if last.is_list():
                self.warn(last, "given twice (lines %d and %d): Peridigm (Teuchos) makes one list of both, a key in "
                          "both taking the later value; so does the converter" % (first.line, last.line))
            else:
                self.warn(last, "given twice (lines %d and %d): Peridigm (Teuchos) keeps the last value, '%s' of "
                          "line %d (line %d said '%s'); so does the converter"
                          % (first.line, last.line, last.value.strip(), last.line, first.line, first.value.strip()))
        for name in self.ESSENTIAL_SECTIONS:
            # Solver1, Solver2, ... stand for Solver.
            if name not in top.children and not (name == "Solver" and any(
                    re.fullmatch(r"Solver\d+", n) for n in top.children)):
                self.messages.append((0, len(self.messages),
                                      "%s:%d: cannot convert '%s': the deck has no %s section"
                                      % (self.deck, top.line, name, name), True))
                self.essential_failures += 1
        if "Material" in top.children:
            self.cannot(self.child(top, "Material"),
                        "the layout of decks before Peridigm 1.0 (one 'Material' list with its damage model "
                        "inside): write 'Materials', 'Damage Models' and 'Blocks' as Peridigm 1.0 does")
        # Solver, Solver1, Solver2, ...: run in the order of their numbers.
        solvers = sorted([n for n in top.children if re.fullmatch(r"Solver\d*", n)],
                         key=lambda n: int(n[6:] or 0))

        self.discretization(self.child(top, "Discretization"))
        self.materials_section(self.child(top, "Materials"))
        self.damage_section(self.child(top, "Damage Models"))
        self.blocks_section(self.child(top, "Blocks"))
        self.scale_hourglass()
        self.check_bonded_blocks(self.child(top, "Blocks"))
        self.check_isolated_points(self.child(top, "Blocks"))
        self.conditions_section(self.child(top, "Boundary Conditions"))
        self.contact_section(self.child(top, "Contact"))
        self.computes_section(self.child(top, "Compute Class Parameters"))
        if solvers:
            end = self.solver_section(self.child(top, solvers[0]))
            solver_types = [self.solver_type]
            stage_names = []
            segments = self.time_step_segments
            if len(solvers) > 1 or segments:
                # Peridigm's later solvers (and the load steps of a QuasiStatic
                # 'Time Steps' list after its first run of equal steps):
                # PeriDeal's Solver stages, each from where the one before ended.
                stages = self.prm.sub("Solver stages")
                stage_names += self.segment_stages(stages, solvers[0].lower(), segments)
                for n in solvers[1:]:
                    name = n.lower()
                    stage_names.append(name)
                    end = self.solver_section(self.child(top, n), out=stages.sub(name), start=end)
                    solver_types.append(self.solver_type)
                    if solver_types[-2] == "QuasiStatic" and self.solver_type in ("Verlet", "Newmark"):
                        # Peridigm's QuasiStatic leaves v = delta u / delta t of its
                        # last load step (Peridigm.cpp, executeQuasiStatic: 'Store the
                        # velocity'), and the next solver starts from it.
                        stages.sub(name).set("Velocity after quasistatic", "load step",
                                             "Peridigm's hand-off: %s starts at the velocity of %s's last load\n"
                                             "step, (u_n - u_(n-1)) / dt; PeriDeal's default (rest) would start it\n"
                                             "with the free points at rest." % (n, solvers[len(solver_types) - 2]))
                    stage_names += self.segment_stages(stages, name, self.time_step_segments)
                stages.set("Names", ", ".join(stage_names), "Peridigm's %s, run after %s in this order%s."
                           % (", ".join(solvers[1:]) or "load steps", solvers[0],
                              " (a QuasiStatic list of Time Steps: one stage per run of equal steps)"
                              if len(stage_names) > len(solvers) - 1 else ""))
            contact = top.children.get("Contact")
            others = sorted(set(t for t in solver_types if t and t != "Verlet"))
            if contact is not None and others:
                self.cannot(contact, "PeriDeal's contact acts in explicit runs only (Type = Verlet), "
                            "not with its %s solver" % others[0])
        # Peridigm makes an output of every top-level list whose name contains
        # "Output" (Peridigm.cpp, initializeOutputManager: name.find("Output")):
        # Output, Output1, Output_2, Output Data, Output History, ...
        outputs = [n for n in top.children if "Output" in n]
        for n in list(outputs):
            if not top.children[n].is_list():
                self.cannot(self.child(top, n), "Peridigm takes every top-level entry whose name contains 'Output' "
                            "for an output list, and this one is a value: Peridigm refuses it ('is not a "
                            "Teuchos::ParameterList sublist')")
                outputs.remove(n)
        self.output_sections([self.child(top, n) for n in outputs])
        self.emit_regions()
        restart = self.child(top, "Restart")
        if restart is not None:
            self.cannot(restart, "Peridigm's restart files are not read; PeriDeal writes its own checkpoints: "
                        "set Output/Checkpoint/Frequency and continue with pd_app --restart (doc/restart.md)",
                        essential=False)
        for c in top.children.values():
            if not c.used:
                c.used = True
                self.cannot(c, "a section the converter does not know")
        return verbose

    # Discretization -------------------------------------------------------

    def discretization(self, d):
        if d is None:
            return
        out = self.prm.sub("Discretization")
        self.from_comment(out, d)
        dtype = self.text(d, "Type", required=True)
        horizon = self.child(d, "Horizon")
        if horizon is not None:
            if horizon.is_list() or not is_number(horizon.value):
                self.cannot(horizon, "a horizon that is not a number (a function of position): PeriDeal "
                            "takes one horizon per block")
                self.disc_horizon = None
            else:
                self.disc_horizon = (num(horizon.value), horizon)
        else:
            self.disc_horizon = None
        filters = self.child(d, "Bond Filters")
        self.peridigm_disc = dtype
        if dtype == "PdQuickGrid":
            norm = self.text(d, "NeighborhoodType")
            node = d.children.get("NeighborhoodType") or d.children.get("Type")
            if norm != "Spherical":
                self.warn(node, "PdQuickGrid without NeighborhoodType = \"Spherical\" builds cube-shaped "
                          "families (every cell within the horizon along each axis, corners included); "
                          "PeriDeal's families are spheres of the horizon: fewer bonds, a different "
                          "stiffness and critical stretch calibration",
                          path=d.path() + "/NeighborhoodType")
                out.comment("TRAP: the Peridigm deck has PdQuickGrid's cube-shaped families (no\n"
                            "NeighborhoodType = Spherical); PeriDeal's families are spheres.")
            box = self.child(d, "TensorProduct3DMeshGenerator")
            cyl = self.child(d, "TensorProductCylinderMeshGenerator")
            if box is not None and cyl is not None:
                self.cannot(cyl, "two mesh generators in one discretization")
            if box is not None:
                self.box(box, out)
            elif cyl is not None:
                self.cylinder(cyl, out)
            else:
                self.cannot(d, "PdQuickGrid needs a TensorProduct3DMeshGenerator or "
                            "TensorProductCylinderMeshGenerator list", path=d.path() + "/Type")
            if filters is not None:
                self.warn(filters, "Peridigm refuses bond filters on a PdQuickGrid discretization "
                          "('Bond filters not supported for PdQuickGrid'); PeriDeal applies them")
        elif dtype == "Exodus":
            mesh = self.text(d, "Input Mesh File", required=True)
            if self.args.mesh:
                self.disc_type = "Gmsh"
                out.set("Type", "Gmsh")
                g = out.sub("Gmsh")
                g.comment("Peridigm's Exodus mesh '%s' replaced by this Gmsh mesh (--mesh):\n"
                          "Exodus block_N is the volume physical group N." % mesh)
                g.set("Mesh file", self.args.mesh)
                others = cells_other_than_hexahedra(self.args.mesh)
                if others:
                    g.set("Cells as points", "true",
                          "The mesh holds %s: each cell becomes one point at its centroid with its volume, as "
                          "Peridigm makes each Exodus element one point." % others)
                self.warn(d.children.get("Input Mesh File") or d,
                          "the Exodus mesh '%s' is replaced by the Gmsh mesh '%s' (--mesh); Exodus block_N "
                          "is taken as Gmsh volume physical group N, node sets as --node-set says"
                          % (mesh, self.args.mesh), path=d.path() + "/Input Mesh File")
            elif mesh is not None:
                self.exodus(d, out, mesh)
        elif dtype == "Text File":
            mesh = self.text(d, "Input Mesh File", required=True)
            self.disc_type = "Text file"
            out.set("Type", "Text file", "Peridigm's Text File: x y z block volume per point.")
            if mesh is not None:
                t = out.sub("Text file")
                here = os.path.join(os.path.dirname(os.path.abspath(self.deck)), mesh)
                if not os.path.isabs(mesh) and os.path.lexists(here):
                    t.comment("'%s' beside the deck; its block N is material id N\n(Blocks/*/Material ids)." % mesh)
                    mesh = os.path.normpath(here)
                else:
                    t.comment("Its block N is material id N (Blocks/*/Material ids); a relative\npath is taken "
                              "from the directory pd_app starts in.")
                problem = regular_file_problem(mesh)
                if problem and os.path.lexists(mesh):
                    self.cannot(d.children.get("Input Mesh File"), "the point file '%s': %s" % (mesh, problem))
                elif problem:
                    self.warn(d.children.get("Input Mesh File"), "the point file '%s' is not found (neither "
                              "beside the deck nor from here)" % mesh)
                self.input_files.append(("the deck's point file", mesh))
                self.point_file = mesh
                t.set("File", mesh)
        elif dtype is not None:
            self.cannot(d.children.get("Type"), "the discretization type '%s' has no PeriDeal equivalent" % dtype)
        if filters is not None:
            self.bond_filters(filters, out)
        omit = self.child(d, "Omit Bonds Between Blocks")
        if omit is not None:
            self.cannot(omit, "PeriDeal bonds every two blocks")
        interfaces = self.child(d, "Construct Interfaces")
        if interfaces is not None:
            # ExodusDiscretization: it keeps the mesh and builds the faces
            # between elements for the interface aperture output only.
            self.cannot(interfaces, "Peridigm's interface faces between elements feed its interface aperture "
                        "output only (the mechanics does not use them); PeriDeal has no such output",
                        essential=False)
        self.leftovers(d)

    def exodus(self, d, out, mesh):
        """Discretization Type Exodus: the deck's mesh itself (beside the deck
        if it is there), its blocks and node sets read by name."""
        self.disc_type = "Exodus"
        out.set("Type", "Exodus", "Peridigm's Exodus mesh, read by PeriDeal itself: hexahedra become a mesh\n"
                "of cells (a point at each cell's centroid), any other elements one point each.")
        e = out.sub("Exodus")
        here = os.path.join(os.path.dirname(os.path.abspath(self.deck)), mesh)
        if not os.path.isabs(mesh) and exodus_pieces(here):
            e.comment("'%s' beside the deck: element block N is material id N." % mesh)
            mesh = os.path.normpath(here)
        else:
            e.comment("Element block N is material id N; a relative path is taken from the\n"
                      "directory pd_app starts in.")
        e.set("Mesh file", mesh)
        for piece in exodus_pieces(mesh):
            self.input_files.append(("the deck's mesh", piece))
        self.exodus_names = ExodusNames(mesh)
        if self.exodus_names.error:
            self.warn(d.children.get("Input Mesh File"), "the mesh's blocks and node sets are not checked: %s"
                      % self.exodus_names.error)

    def box(self, g, out):
        self.disc_type = "Box"
        out.set("Type", "Box")
        b = out.sub("Box")
        b.comment("PdQuickGrid TensorProduct3DMeshGenerator: Number Points X/Y/Z cells of the\n"
                  "box from the origin over the lengths, one point at each cell's centre, as in\n"
                  "Peridigm.")
        origin, length, n = [], [], []
        for axis in "XYZ":
            origin.append(self.number(g, "%s Origin" % axis, required=True))
            length.append(self.number(g, "%s Length" % axis, required=True))
            n.append(self.number(g, "Number Points %s" % axis, required=True, integer=True))
        self.child(g, "Type")  # PdQuickGrid, repeated in the users' guide
        if None not in origin + length + n:
            b.set("Lower corner", ",".join(origin))
            b.set("Upper corner", ",".join(fmt(float(o) + float(l)) for o, l in zip(origin, length)))
            b.set("Subdivisions", ",".join(str(int(x)) for x in n))
        self.leftovers(g)

    def cylinder(self, g, out):
        self.disc_type = "Cylinder shell"
        out.set("Type", "Cylinder shell")
        c = out.sub("Cylinder shell")
        ri = self.number(g, "Inner Radius", required=True)
        ro = self.number(g, "Outer Radius", required=True)
        length = self.number(g, "Cylinder Length", required=True)
        cx = self.number(g, "Ring Center x", required=True)
        cy = self.number(g, "Ring Center y", required=True)
        z0 = self.number(g, "Z Origin", required=True)
        nr = self.number(g, "Number Points Radius", required=True, integer=True)
        self.child(g, "Type")  # PdQuickGrid, repeated in the users' guide
        if nr is not None and int(nr) < 1:
            self.cannot(g.children["Number Points Radius"], "must be at least 1, got %s" % nr)
            nr = None
        if ri is not None and ro is not None and float(ro) <= float(ri):
            self.cannot(g.children["Outer Radius"], "must be larger than the Inner Radius %s, got %s" % (ri, ro))
            ro = None
        if None in (ri, ro, length, cx, cy, z0, nr):
            self.leftovers(g)
            return
        c.set("Inner radius", ri)
        c.set("Outer radius", ro)
        c.set("Length", length)
        c.set("Center x", cx)
        c.set("Center y", cy)
        c.set("Z origin", z0)
        c.set("Radial cells", str(int(nr)), "Peridigm's 'Number Points Radius'.")
        # Peridigm (PdQuickGrid): cell size = thickness / rings, cells along
        # the axis = (int)(length / cell size) + 1; the cells around: PeriDeal's
        # default 0 follows Peridigm's rule.
        dr = (float(ro) - float(ri)) / int(nr)
        axial = int(float(length) / dr) + 1 if dr > 0 else 0
        c.set("Circumferential cells", "0", "0: the mid-radius circumference over the radial spacing, rounded\n"
              "down, as PdQuickGrid does.")
        c.set("Axial cells", str(axial), "PdQuickGrid's count: (int)(length / radial spacing) + 1.")
        self.leftovers(g)

    def bond_filters(self, f, out):
        bf = out.sub("Bond filters")
        bf.comment("Peridigm's Rectangular_Plane: the rectangle spans Bottom_Length from the\n"
                   "corner along Bottom_Unit_Vector and Side_Length along Bottom_Unit_Vector x\n"
                   "Normal. PeriDeal's bond filters take the side along the same product, so the\n"
                   "vectors are copied as they are (TRAP: a deck written for PeriDeal before\n"
                   "December 2026, which took Normal x Bottom unit vector, had Normal negated).")
        names = []
        for c in self.list_entries(f, "a bond filter is a list"):
            ftype = self.text(c, "Type", required=True)
            if ftype != "Rectangular_Plane":
                if ftype is not None:
                    self.cannot(c.children.get("Type"), "bond filter type '%s': PeriDeal has rectangular "
                                "planes only" % ftype)
                self.skip(c)
                continue
            vals = {}
            for key in ("Normal", "Lower_Left_Corner", "Bottom_Unit_Vector"):
                vals[key] = [self.number(c, "%s_%s" % (key, a), required=True) for a in "XYZ"]
            for key in ("Bottom_Length", "Side_Length"):
                vals[key] = self.number(c, key, required=True)
            self.leftovers(c)
            s = bf.sub(c.name)
            self.from_comment(s, c)
            s.set("Type", "Rectangular plane")
            normal = ",".join(v or "0" for v in vals["Normal"])
            bottom = ",".join(v or "0" for v in vals["Bottom_Unit_Vector"])
            lengths = (vals["Bottom_Length"] or "0", vals["Side_Length"] or "0")
            if None not in vals["Normal"] + vals["Bottom_Unit_Vector"] and None not in lengths:
                exact = self.peridigm_rectangle(c, [float(v) for v in vals["Normal"]],
                                                [float(v) for v in vals["Bottom_Unit_Vector"]],
                                                float(vals["Bottom_Length"]), float(vals["Side_Length"]))
                if exact is not None:
                    bottom, lengths, comment = exact
                    s.comment(comment)
            s.set("Normal", normal)
            s.set("Lower left corner", ",".join(v or "0" for v in vals["Lower_Left_Corner"]))
            s.set("Bottom unit vector", bottom)
            s.set("Bottom length", lengths[0])
            s.set("Side length", lengths[1])
            names.append(c.name)
        bf.items.insert(0, ["set", "Names", ", ".join(names)])

    def peridigm_rectangle(self, c, n, ub, b, a):
        """Peridigm's Rectangular_Plane with the vectors as given (PdBondFilter:
        the plane through the corner with normal n, and a crossing point x cut
        when 0 <= (x - r0).ub <= b and 0 <= (x - r0).ua <= a, ua = ub x n, none
        of them normalised) as PeriDeal's rectangle (unit vectors, the bottom
        perpendicular to the normal): in the plane only ub's part p = ub -
        (ub.n^) n^ counts, and ua = p x n, so the region is the rectangle along
        p / |p| of length b / |p| and side a / (|p| |n|). None (nothing to
        change) when the vectors are unit and perpendicular to 1e-12; else
        (bottom unit vector, (bottom length, side length), comment)."""
        nn = math.sqrt(sum(x * x for x in n))
        if nn == 0:
            return None  # pd_app says why
        nh = [x / nn for x in n]
        d = sum(x * y for x, y in zip(ub, nh))
        p = [x - d * y for x, y in zip(ub, nh)]
        pn = math.sqrt(sum(x * x for x in p))
        if abs(nn - 1) <= 1e-12 and abs(pn - 1) <= 1e-12 and abs(d) <= 1e-12:
            return None
        if pn <= 1e-12 * math.sqrt(sum(x * x for x in ub)):
            self.cannot(c, "Bottom_Unit_Vector is along Normal: Peridigm's filter then cuts every bond through the "
                        "whole plane, PeriDeal's rectangles are finite", path=c.path() + "/Bottom_Unit_Vector_X")
            return None
        bottom = [x / pn for x in p]
        lengths = (fmt(b / pn), fmt(a / (pn * nn)))
        text = ",".join(fmt(x) for x in bottom)
        self.warn(c, "Normal (length %.6g) and Bottom_Unit_Vector (length %.6g, at %.6g degrees from the plane) are not "
                  "unit and perpendicular: Peridigm uses them as given, which cuts the rectangle along Bottom_Unit_Vector's "
                  "part in the plane, Bottom_Length / %.6g long and Side_Length / %.6g wide: written as Bottom unit "
                  "vector = %s, Bottom length = %s, Side length = %s (the bonds Peridigm cuts)"
                  % (nn, math.sqrt(sum(x * x for x in ub)), math.degrees(math.asin(min(1.0, abs(d) / math.sqrt(
                      sum(x * x for x in ub))))), pn, pn * nn, text, lengths[0], lengths[1]))
        comment = ("Peridigm uses Normal and Bottom_Unit_Vector as given (not unit or not\n"
                   "perpendicular here): its rectangle runs along Bottom_Unit_Vector's part p in\n"
                   "the plane, |p| = %s, Bottom_Length / |p| long and Side_Length /\n"
                   "(|p| |Normal|) wide, |Normal| = %s: the same rectangle in unit vectors." % (fmt(pn), fmt(nn)))
        return text, lengths, comment

    # Materials --------------------------------------------------------------

    MODELS = {
        "Elastic": "LPS",
        "Elastic Bond Based": "PMB",
        "Elastic Plastic": "Elastic plastic",
        "Elastic Plastic Hardening": "Elastic plastic",
        "Viscoelastic": "Viscoelastic",
        "Elastic Correspondence": "Elastic correspondence",
        "Elastic Plastic Correspondence": "Elastic plastic correspondence",
        "Elastic Plastic Hardening Correspondence": "Elastic plastic correspondence",
        "Isotropic Hardening Correspondence": "Elastic plastic correspondence",
        "Linear LPS Partial Volume": "LPS",
    }
    MODULI = (("Bulk Modulus", "Bulk modulus"), ("Shear Modulus", "Shear modulus"),
              ("Young's Modulus", "Young's modulus"), ("Poisson's Ratio", "Poisson's ratio"))

    def materials_section(self, m):
        if m is None:
            return
        out = self.prm.sub("Materials")
        self.from_comment(out, m)
        names = []
        for c in self.list_entries(m, "a material is a list of its properties"):
            model = self.text(c, "Material Model", required=True)
            if model is None:
                self.skip(c)
                continue
            if model not in self.MODELS:
                self.cannot(c.children["Material Model"], "the material model '%s' has no PeriDeal "
                            "equivalent (PeriDeal has Peridigm's %s)"
                            % (model, ", ".join("'%s'" % k for k in self.MODELS)))
                self.skip(c)
                continue
            s = out.sub(c.name)
            self.from_comment(s, c)
            pmodel = self.MODELS[model]
            s.set("Model", pmodel, "Peridigm's '%s'." % model)
            self.materials[c.name] = pmodel
            density = self.number(c, "Density", required=True)
            if density is not None:
                s.set("Density", density)
            given = 0
            for key, pkey in self.MODULI:
                v = self.number(c, key)
                if v is not None:
                    s.set(pkey, v)
                    given += 1
            if given == 0:
                self.cannot(c, "no elastic constant (Bulk Modulus, Shear Modulus, Young's Modulus, "
                            "Poisson's Ratio)", path=c.path())
            v = self.number(c, "Thermal Expansion Coefficient")
            if v is not None:
                s.set("Thermal expansion coefficient", v)
            ad = self.child(c, "Apply Automatic Differentiation Jacobian")
            if ad is not None:
                s.comment("Peridigm's 'Apply Automatic Differentiation Jacobian' is not needed: PeriDeal's\n"
                          "PMB and LPS tangents are analytic (Solver/Implicit/Tangent).")
            scf = self.boolean(c, "Apply Shear Correction Factor")
            if model == "Elastic":
                if scf:
                    self.cannot(c.children["Apply Shear Correction Factor"],
                                "Peridigm's shear correction factor (a per-point scaling of the deviatoric "
                                "stiffness near surfaces) is not PeriDeal's; 'Surface correction = Energy' "
                                "is Le and Bobaru's energy method, a different correction")
                else:
                    s.comment("TRAP: Peridigm versions after 1.0 apply a shear correction factor to\n"
                              "'Elastic' unless 'Apply Shear Correction Factor' is false; PeriDeal's LPS\n"
                              "has none (Surface correction = None).")
            if model in ("Elastic Plastic", "Elastic Plastic Hardening", "Elastic Plastic Correspondence",
                         "Elastic Plastic Hardening Correspondence", "Isotropic Hardening Correspondence"):
                y = self.number(c, "Yield Stress", required=True)
                if y is not None:
                    s.set("Yield stress", y)
                dp = self.boolean(c, "Disable Plasticity")
                if dp:
                    self.cannot(c.children["Disable Plasticity"], "PeriDeal's plastic models cannot be made "
                                "elastic; use Material Model Elastic")
            if model in ("Elastic Plastic Hardening", "Elastic Plastic Hardening Correspondence",
                         "Isotropic Hardening Correspondence"):
                h = self.number(c, "Hardening Modulus", required=True)
                if h is not None:
                    s.set("Hardening modulus", h)
                    if model == "Elastic Plastic Hardening" and float(h) != 0:
                        self.warn(c.children["Hardening Modulus"],
                                  "Peridigm hardens the yield function in force-state units, PeriDeal's "
                                  "Hardening modulus is the J2 slope in stress units (doc/inelastic.md): "
                                  "the same number hardens differently")
            if model == "Viscoelastic":
                li = self.number(c, "lambda_i", required=True)
                tb = self.number(c, "tau b", required=True)
                if li is not None:
                    s.set("Viscous fraction", li, "Peridigm's 'lambda_i'.")
                if tb is not None:
                    s.set("Relaxation time", tb, "Peridigm's 'tau b'.")
            if "Correspondence" in model:
                hg = self.number(c, "Hourglass Coefficient", required=True)
                if hg is not None:
                    s.set("Stabilization", "Hourglass")
                    s.set("Hourglass coefficient", hg)  # scaled by scale_hourglass() once the horizons are known
                    self.hourglass[c.name] = (hg, c.children["Hourglass Coefficient"], s)
                if model == "Elastic Correspondence":
                    s.set("Strain measure", "Green-Lagrange",
                          "TRAP: Peridigm 1.5's Elastic Correspondence is hypoelastic (the unrotated\n"
                          "Cauchy stress integrated from the unrotated rate of deformation, as its\n"
                          "plastic correspondence models); PeriDeal's Elastic correspondence is\n"
                          "hyperelastic (Green-Lagrange, St. Venant-Kirchhoff) or corotational small\n"
                          "strain. The two agree at small strains only (stresses about 2e-3 apart\n"
                          "at 0.1% strain). PeriDeal's hypoelastic correspondence law is Elastic\n"
                          "plastic correspondence's: with a Yield stress above every stress reached\n"
                          "it is Peridigm's Elastic Correspondence (doc/peridigm.md).")
                    self.warn(c.children["Material Model"], "Peridigm 1.5's Elastic Correspondence is hypoelastic "
                              "(unrotated Cauchy stress rate), written as PeriDeal's Elastic correspondence with "
                              "Strain measure = Green-Lagrange (hyperelastic): the same at small strains only; "
                              "PeriDeal's hypoelastic law is Elastic plastic correspondence's (with a Yield stress "
                              "no stress reaches it is Peridigm's Elastic Correspondence)")
            if self.MODELS[model] == "Elastic plastic correspondence":
                s.set("Yield stress measure", "Cauchy",
                      "Peridigm yields on the von Mises stress of the Cauchy stress; PeriDeal's\n"
                      "default (Kirchhoff) yields on J times it (doc/models.md).")
                self.warn(c.children["Material Model"], "written with Yield stress measure = Cauchy: Peridigm yields "
                          "on the Cauchy von Mises stress, PeriDeal's default (Kirchhoff) on J times it")
            if model in ("Elastic Plastic", "Elastic Plastic Hardening"):
                s.comment("TRAP: Peridigm's yield constant is the continuum family's, 25 Y^2 / (8 pi\n"
                          "delta^5); PeriDeal's is the point's own, 5 Y^2 / (2 m_i): the same inside\n"
                          "a full family, near a surface PeriDeal yields at von Mises stress Y\n"
                          "(doc/inelastic.md).")
                self.warn(c.children["Material Model"], "Peridigm's yield constant is the continuum family's "
                          "(25 Y^2 / (8 pi delta^5)), PeriDeal's the point's own (5 Y^2 / (2 m_i)): the same inside a "
                          "full family, different near surfaces (doc/inelastic.md)")
            if model == "Linear LPS Partial Volume":
                self.warn(c.children["Material Model"], "PeriDeal's LPS is the ordinary (not linearized) "
                          "model and its partial volumes come from the cells' geometry "
                          "(Discretization/Partial volumes = true): small deformations only agree")
                self.prm.sub("Discretization").set("Partial volumes", "true")
            if "Correspondence" not in model and "Hourglass Coefficient" in c.children:
                self.child(c, "Hourglass Coefficient")
                self.warn(c.children["Hourglass Coefficient"], "ignored: Peridigm's '%s' has no hourglass force and "
                          "does not read the key, and neither does the converter" % model)
            self.influence_function(c, s, model)
            self.flaw(c, model)
            self.leftovers(c)
            names.append(c.name)
        out.items.insert(len([i for i in out.items if i[0] == "comment"]), ["set", "Names", ", ".join(names)])

    # Peridigm's predefined influence functions of zeta = |xi| and the horizon
    # (Peridigm_InfluenceFunction.hpp) as PeriDeal's Influence function of
    # r = |xi| / horizon.
    INFLUENCE = {
        "One": "1",
        "Parabolic Decay": "(r<0.5) ? 1 : (-4*r*r+4*r)",
        "Gaussian": "exp(-r*r)",
    }

    def influence_function(self, c, s, model):
        """Peridigm's 'Influence Function' as LPS's Influence function; the
        other PeriDeal models take omega = 1 only."""
        node = self.child(c, "Influence Function")
        if node is None:
            return
        if node.is_list():
            self.cannot(node, "a value was expected, not a list")
            return
        name = node.value.strip()
        expr = self.INFLUENCE.get(name)
        if expr is None:
            self.cannot(node, "the user-defined influence function '%s' (a function of zeta and the horizon): "
                        "PeriDeal's Influence function is a muparser expression in r = |xi|/horizon; write it "
                        "there by hand (Peridigm's predefined ones, %s, are converted)"
                        % (name, ", ".join(self.INFLUENCE)))
            return
        if self.MODELS[model] == "LPS":
            s.set("Influence function", expr, "Peridigm's Influence Function '%s' (Peridigm_InfluenceFunction.hpp), "
                  "in r = |xi|/horizon." % name)
        elif expr != "1":
            self.cannot(node, "PeriDeal's %s weighs every bond by omega = 1; only its LPS takes an Influence "
                        "function" % self.MODELS[model])

    FLAW_KEYS = ("Enable Flaw", "Flaw Location X", "Flaw Location Y", "Flaw Location Z", "Flaw Size",
                 "Flaw Magnitude")

    def flaw(self, c, model):
        """Peridigm's material flaw (a yield stress lowered around a point,
        Y (1 - M exp(-|x - x_f|^2 / s^2)), in its plastic correspondence
        models): nothing to convert when it is off ('Enable Flaw' false or
        absent: Peridigm reads none of its keys); PeriDeal has no yield stress
        that varies in space, so an enabled flaw is refused."""
        keys = [k for k in self.FLAW_KEYS if k in c.children]
        if not keys:
            return
        enabled = self.boolean(c, "Enable Flaw") if "Enable Flaw" in c.children else False
        for k in keys:
            self.child(c, k)
        if enabled:
            self.cannot(c.children["Enable Flaw"], "PeriDeal's yield stress is one number per material: Peridigm's "
                        "flaw (the yield stress lowered around Flaw Location by Flaw Magnitude over Flaw Size) has "
                        "no counterpart")

    # Damage models ----------------------------------------------------------

    DAMAGE = {
        "Critical Stretch": "Critical stretch",
        "Interface Aware": "Interface aware",
        "Time Dependent Critical Stretch": "Time dependent critical stretch",
        "User Defined Time Dependent Critical Stretch": "Time dependent critical stretch",
        "Von Mises Stress": "Von Mises stress",
        "Critical Energy": "Critical energy",
    }

    def damage_section(self, m):
        if m is None:
            return
        out = self.prm.sub("Damage models")
        self.from_comment(out, m)
        names = []
        for c in self.list_entries(m, "a damage model is a list of its properties"):
            model = self.text(c, "Damage Model", required=True)
            if model is None:
                self.skip(c)
                continue
            if model not in self.DAMAGE:
                self.cannot(c.children["Damage Model"], "the damage model '%s' has no PeriDeal equivalent "
                            "(PeriDeal has Peridigm's %s)" % (model, ", ".join("'%s'" % k for k in self.DAMAGE)))
                self.skip(c)
                continue
            s = out.sub(c.name)
            self.from_comment(s, c)
            s.set("Model", self.DAMAGE[model], "Peridigm's '%s'." % model)
            self.damage_models[c.name] = self.DAMAGE[model]
            if model in ("Critical Stretch", "Interface Aware"):
                v = self.number(c, "Critical Stretch", required=True)
                if v is not None:
                    s.set("Critical stretch", v)
                if model == "Interface Aware":
                    s.comment("Interface critical stretch 0: s_c at the interface too, Peridigm's rule.")
            elif model.endswith("Time Dependent Critical Stretch"):
                key = "Time Dependent Critical Stretch"
                expr_node = self.child(c, key) or self.child(c, "Critical Stretch")
                if expr_node is None or expr_node.is_list():
                    self.cannot(c, "'%s' is missing" % key, path=c.path() + "/" + key)
                else:
                    try:
                        s.set("Critical stretch", translate_expression(expr_node.value, ("t",)),
                              "Peridigm's function of t: %s" % expr_node.value.strip())
                    except ExprError as e:
                        self.cannot(expr_node, "the function '%s': %s" % (expr_node.value.strip(), e))
            elif model == "Critical Energy":
                self.critical_energy(c, s)
            elif model == "Von Mises Stress":
                for key, pkey in (("Critical Von Mises Stress", "Critical von Mises stress"),
                                  ("Critical Damage", "Critical damage"), ("Threshold Damage", "Threshold damage")):
                    v = self.number(c, key, required=(key == "Critical Von Mises Stress"))
                    if v is not None:
                        s.set(pkey, v)
            v = self.number(c, "Critical Damage To Neglect Material Point")
            if v is None:
                v = self.number(c, "Critical Damage to Neglect Material Point")
            if v is not None:
                s.set("Critical damage to neglect material point", v)
            tec = self.child(c, "Thermal Expansion Coefficient")
            if tec is not None:
                self.cannot(tec, "PeriDeal's stretch criteria compare the total stretch (no thermal part "
                            "subtracted)")
            self.leftovers(c)
            names.append(c.name)
        out.items.insert(len([i for i in out.items if i[0] == "comment"]), ["set", "Names", ", ".join(names)])
        if names:
            out.comment("TRAP: Peridigm's damage of a point is the fraction of its broken bonds by\n"
                        "count, PeriDeal's by neighbour volume: the same on cells of one volume\n"
                        "(Box, Cylinder shell, a regular mesh), different on unequal cells.")
            self.warn(m, "Peridigm counts a point's damage by broken bonds, PeriDeal by their neighbours' volume: the "
                      "same on cells of one volume, different on unequal cells (the bonds broken are the same, "
                      "the Damage field is not)")

    def critical_energy(self, c, s):
        """Peridigm's Critical Energy (DLR's EnergyReleaseDamageModel): its
        'Critical Energy' G (or, alone, 'Critical Energy Tension') is PeriDeal's
        Critical energy release rate. Peridigm's Energy Criterion breaks a bond
        when (|t_ij| + |t_ji|) e > 8 G / (pi delta^4) (t the LPS scalar force
        state, e the extension), PeriDeal when its bond energy (t_ij + t_ji) e / 2
        > 4 G_c / (pi delta^4): the same bonds in tension for G_c = G."""
        g = self.number(c, "Critical Energy")
        if g is None:
            tension = self.child(c, "Critical Energy Tension")
            others = [k for k in ("Critical Energy Compression", "Critical Energy Shear", "Power Law", "Separated")
                      if k in c.children]
            if tension is not None and not others:
                g = self.number(c, "Critical Energy Tension")
            elif tension is None and not others:
                self.cannot(c, "'Critical Energy' is missing", path=c.path() + "/Critical Energy")
        for key in ("Critical Energy Compression", "Critical Energy Shear", "Power Law", "Separated"):
            k = self.child(c, key)
            if k is not None:
                self.cannot(k, "PeriDeal's Critical energy has one G_c for a bond's whole energy (and compression "
                            "breaks nothing): no separate tension, compression and shear energies or criteria")
        for k in [k for k in c.children.values() if k.name.startswith("Interblock")]:
            k.used = True
            self.cannot(k, "PeriDeal's Critical energy has no energy of its own for bonds between blocks (a block with "
                        "it bonds only to blocks with the same damage model and horizon)")
        only = self.boolean(c, "Only Tension")
        if only is False:
            self.cannot(c.children["Only Tension"], "PeriDeal's Critical energy breaks stretched bonds only")
        for key in ("Plane Stress", "Plane Strain"):
            if self.boolean(c, key):
                self.cannot(c.children[key], "PeriDeal's w_c = 4 G_c / (pi delta^4) is the three-dimensional one")
        detached = self.child(c, "Detached Nodes Check")
        if detached is not None:
            self.cannot(detached, "PeriDeal has no such check; its 'Critical damage to neglect material point' "
                        "frees a point that has lost its bonds", essential=False)
        factor = self.number(c, "Degradation Factor")
        if factor is not None and float(factor) != 1:
            self.cannot(c.children["Degradation Factor"], "PeriDeal breaks a bond at once (a degradation factor of 1)")
        if g is not None:
            s.set("Critical energy release rate", g,
                  "Peridigm's Critical Energy: it breaks a bond when (|t_ij| + |t_ji|) e\n"
                  "> 8 G / (pi delta^4), PeriDeal when (t_ij + t_ji) e / 2 > 4 G_c / (pi delta^4):\n"
                  "the same bonds in tension for G_c = G (doc/peridigm.md).")
            self.warn(c.children.get("Critical Energy") or c.children.get("Critical Energy Tension"),
                      "written as Critical energy release rate = %s: Peridigm's Energy Criterion ((|t_ij| + "
                      "|t_ji|) e > 8 G / (pi delta^4)) breaks the bonds of an Elastic (LPS) block in tension "
                      "where PeriDeal's does; Peridigm defines it for Elastic blocks only, PeriDeal uses each "
                      "material's own bond energy; DLR's first version compared with 16 G / (pi delta^4): for "
                      "a deck written for it, double the value" % g)

    def block_horizons(self):
        """[(PeriDeal block name, material, damage model, horizon text or None)]."""
        disc_h = self.disc_horizon[0] if getattr(self, "disc_horizon", None) else None
        out = []
        for c, dnames, material, damage, h in getattr(self, "peridigm_blocks", []):
            name = dnames[0] if len(dnames) == 1 else c.name
            out.append((name, material, damage, h[0] if h else disc_h))
        return out

    def scale_hourglass(self):
        """Peridigm's hourglass force on a bond is |Y| times PeriDeal's for the
        same coefficient C (doc/models.md: Peridigm multiplies by Y where PeriDeal
        has Y/|Y|). No constant makes them equal bond by bond; C' = C 2 delta / 3
        makes the two forces' total stiffness against a zero-energy mode (|z.M|
        the same on every bond) equal for a full spherical family: C' sum_j V_j /
        |xi| = C sum_j V_j, and the mean of 1/|xi| over a sphere is 3 / (2 delta)."""
        blocks = self.block_horizons()
        for material, (hg, node, s) in self.hourglass.items():
            horizons = sorted(set(float(h) for _, m, _, h in blocks if m == material and h is not None))
            if not horizons:
                self.warn(node, "Peridigm's hourglass force is |Y| times PeriDeal's for the same coefficient, and "
                          "no block with a horizon uses this material: copied as it is, not scaled by 2 delta / 3")
                continue
            delta = horizons[0]
            scaled = float(hg) * 2 * delta / 3
            s.set("Hourglass coefficient", "%.12g" % scaled,
                  "Peridigm's Hourglass Coefficient %s x 2 delta / 3, delta = %s.\n"
                  "Peridigm's hourglass force on a bond is |Y| times PeriDeal's for the same\n"
                  "coefficient, so none is exact; this one gives the same total stiffness\n"
                  "against a zero-energy mode for a full spherical family (the mean of 1/|xi|\n"
                  "over it is 3 / (2 delta)).\n"
                  "In the deck's unit of length." % (hg, "%g" % delta))
            self.warn(node, "written as Hourglass coefficient = %s x 2 x %g / 3 = %.6g: Peridigm's hourglass force "
                      "on a bond is |Y| times PeriDeal's for the same coefficient (doc/models.md); the two agree "
                      "in total stiffness for a full spherical family, not bond by bond (short bonds are stiffer, "
                      "long ones softer in PeriDeal)" % (hg, delta, scaled))
            if len(horizons) > 1:
                self.warn(node, "the blocks of this material have different horizons (%s): scaled with the "
                          "smallest" % ", ".join("%g" % h for h in horizons))

    OWN_LAW_DAMAGE = ("Critical energy", "Von Mises stress")  # not a stretch criterion (pd_app's force_model.cc)
    HORIZON_ONE = ("LPS", "Elastic plastic", "Viscoelastic", "Elastic correspondence",
                   "Elastic plastic correspondence")

    def check_bonded_blocks(self, node):
        """What pd_app refuses of blocks within a horizon of each other, which
        the converter cannot see (it does not know which blocks touch): named
        as warnings with what to do."""
        blocks = self.block_horizons()
        if node is None or len(blocks) < 2:
            return
        models = {}
        for name, material, _, _ in blocks:
            models.setdefault(self.materials.get(material), []).append(name)
        models.pop(None, None)
        if len(models) > 1:
            self.warn(node, "the blocks have different material models (%s): pd_app refuses blocks of different "
                      "models within a horizon of each other ('bonds between models are not defined'). If they "
                      "touch, give them one model with different constants; different models only for blocks "
                      "more than a horizon apart (e.g. meeting by contact)"
                      % "; ".join("%s: %s" % (m, ", ".join(n)) for m, n in sorted(models.items())))
        damage = {name: self.damage_models.get(d) for name, _, d, _ in blocks}
        if any(d in self.OWN_LAW_DAMAGE for d in damage.values()) and len(set(damage.values())) > 1:
            self.warn(node, "the blocks have different damage models (%s), and %s decides by a law of its own: "
                      "pd_app refuses two such blocks within a horizon of each other (the two halves of a bond "
                      "would follow different laws). If they touch, give them the same damage model"
                      % ("; ".join("%s: %s" % (n, d or "none") for n, d in damage.items()),
                         " or ".join(sorted(set(d for d in damage.values() if d in self.OWN_LAW_DAMAGE)))))
        horizons = set(h for _, _, _, h in blocks if h is not None)
        uneven = sorted(set(self.materials.get(m) for _, m, _, _ in blocks) & set(self.HORIZON_ONE))
        if len(horizons) > 1 and uneven:
            self.warn(node, "the blocks have different horizons (%s): pd_app's %s refuse blocks of different horizons "
                      "bonded to each other (and Critical energy blocks sharing bonds need one horizon): give the "
                      "blocks that touch one horizon" % (", ".join(sorted(horizons)), ", ".join(uneven)))

    def check_isolated_points(self, node):
        """Points with no neighbour within their block's horizon, where the
        converter has the points (a Box, a Text File): Peridigm runs them (such
        a point moves freely under its conditions), and so does pd_app with a
        warning, but it refuses a body all of whose points are such (outside
        contact) and holds them in place in a quasistatic solve: a comment and
        a warning with how many."""
        blocks = {dn[0]: (h[0] if h else None) for _, dn, _, _, h in getattr(self, "peridigm_blocks", [])}
        disc_h = self.disc_horizon[0] if getattr(self, "disc_horizon", None) else None
        horizon = {name: float(h if h is not None else disc_h) for name, h in blocks.items()
                   if h is not None or disc_h is not None}
        if node is None or not horizon:
            return
        points = []  # (x, y, z, block name)
        if self.disc_type == "Box" and "block_1" in horizon:
            d = self.prm.sub("Discretization").sub("Box")
            get = {i[1]: i[2] for i in d.items if i[0] == "set"}
            try:
                lo = [float(v) for v in get["Lower corner"].split(",")]
                hi = [float(v) for v in get["Upper corner"].split(",")]
                n = [int(v) for v in get["Subdivisions"].split(",")]
            except (KeyError, ValueError):
                return
            spacings = [(b - a) / k for a, b, k in zip(lo, hi, n) if k > 1]
            total = n[0] * n[1] * n[2]
            isolated = total if not spacings or horizon["block_1"] < min(spacings) * (1 - 1e-9) else 0
            where = "every point (the spacing %s exceeds the horizon %s)" % (
                fmt(min(spacings)) if spacings else "-", fmt(horizon["block_1"]))
        elif self.disc_type == "Text file" and getattr(self, "point_file", None):
            try:
                with open_regular(self.point_file, "the point file") as f:
                    for raw in f:
                        t = raw.decode("utf-8", "replace").split("#")[0].split()
                        if len(t) >= 5:
                            points.append((float(t[0]), float(t[1]), float(t[2]), "block_%d" % int(float(t[3]))))
            except (InputError, OSError, ValueError):
                return
            if not points or len(points) > 2000000:
                return
            cell = max(horizon.values())
            grid = {}
            for i, (x, y, z, _) in enumerate(points):
                grid.setdefault((math.floor(x / cell), math.floor(y / cell), math.floor(z / cell)), []).append(i)
            isolated, first = 0, None
            for i, (x, y, z, b) in enumerate(points):
                h = horizon.get(b)
                if h is None:
                    continue
                cx, cy, cz = math.floor(x / cell), math.floor(y / cell), math.floor(z / cell)
                found = False
                for key in ((cx + a, cy + b2, cz + c) for a in (-1, 0, 1) for b2 in (-1, 0, 1) for c in (-1, 0, 1)):
                    for j in grid.get(key, ()):
                        if j != i and (points[j][0] - x) ** 2 + (points[j][1] - y) ** 2 + (points[j][2] - z) ** 2 \
                                <= (h * (1 + 1e-9)) ** 2:
                            found = True
                            break
                    if found:
                        break
                if not found:
                    isolated += 1
                    first = first or (x, y, z, b)
            total = len(points)
            where = "the first at (%s, %s, %s) in %s" % (fmt(first[0]), fmt(first[1]), fmt(first[2]), first[3]) \
                if first else ""
        else:
            return
        if not isolated:
            return
        # pd_app refuses a body without a bond, outside contact (a deck with
        # Contact: its blocks' points may be free particles).
        top = getattr(node, "parent", None)
        every = isolated == total and not (top is not None and "Contact" in getattr(top, "children", {}))
        self.prm.sub("Discretization").comment(
            "TRAP: %d of the %d points have no neighbour within the horizon. Peridigm\n"
            "runs them: such a point moves freely under its conditions, and so does\n"
            "pd_app's (with a warning). pd_app refuses a body all of whose points are\n"
            "such (outside contact: a horizon below the point spacing), and a\n"
            "quasistatic solve holds them in place (an Error if a load acts on one)."
            % (isolated, total))
        self.warn(node, "%d of the %d points have no neighbour within the horizon (%s): Peridigm runs them (each "
                  "moves freely under its conditions), and so does pd_app with a warning%s; a quasistatic solve "
                  "holds them in place" % (isolated, total, where,
                                           ", but not when every point is one outside contact, as here"
                                           if every else ""))

    # Blocks -----------------------------------------------------------------

    def blocks_section(self, b):
        if b is None:
            return
        out = self.prm.sub("Blocks")
        self.from_comment(out, b)
        entries = []
        for c in self.list_entries(b, "a block is a list (Block Names, Material, ...)"):
            names = self.text(c, "Block Names", required=True)
            material = self.text(c, "Material", required=True)
            damage = self.text(c, "Damage Model")
            horizon = self.child(c, "Horizon")
            h = None
            if horizon is not None:
                if horizon.is_list() or not is_number(horizon.value):
                    self.cannot(horizon, "a horizon that is not a number (a function of position): PeriDeal "
                                "takes one horizon per block")
                else:
                    h = (num(horizon.value), horizon)
            deck_materials = self.root.children.get("Materials")
            if material is not None and (deck_materials is None or material not in deck_materials.children):
                self.cannot(c.children["Material"], "no material '%s' in Materials" % material)
            deck_damage = self.root.children.get("Damage Models")
            if damage is not None and (deck_damage is None or damage not in deck_damage.children):
                self.cannot(c.children["Damage Model"], "no damage model '%s' in Damage Models" % damage)
            self.leftovers(c)
            entries.append((c, (names or "").split(), material, damage, h))
        entries = self.expand_default(b, entries)
        # One PeriDeal block per mesh block (named as Peridigm names it,
        # block_N): an entry that lists several mesh blocks ('block_1
        # block_2') gives each its own block with the entry's material, damage
        # model and horizon. Peridigm keeps its mesh blocks apart inside an
        # entry (general contact acts between them, and Interface Aware sees
        # their interface), which one PeriDeal block of all would not.
        blocks = []  # (entry node, mesh block name, material, damage, horizon)
        seen = {}
        for c, dnames, material, damage, h in entries:
            for dn in dnames:
                if dn in seen:
                    self.cannot(c.children.get("Block Names") or c, "the mesh block '%s' is given a material twice "
                                "(also in '%s')" % (dn, seen[dn].path()))
                    continue
                seen[dn] = c
                blocks.append((c, dn, material, damage, h))
                self.block_map[dn] = dn
        # One horizon for all: Discretization/Horizon.
        block_h = [e[4][0] if e[4] else None for e in blocks]
        disc_h = self.disc_horizon[0] if getattr(self, "disc_horizon", None) else None
        common = None
        if disc_h is None and block_h and all(x is not None for x in block_h) and len(set(block_h)) == 1:
            common = block_h[0]
        if disc_h is not None or common is not None:
            d = self.prm.sub("Discretization")
            if disc_h is not None:
                d.set("Horizon", disc_h)
            else:
                d.set("Horizon", common, "Peridigm gives the horizon per block (Blocks/*/Horizon); every block\n"
                      "has %s." % common)
        no_horizon = set()
        for c, dn, material, damage, h in blocks:
            s = out.sub(dn)
            self.from_comment(s, c)
            group = c.__dict__.get("mesh_blocks", [])
            if len(group) > 1:
                s.comment("One of the mesh blocks %s of Peridigm's '%s':\n"
                          "each is a PeriDeal block of its own, as in Peridigm (contact acts\n"
                          "between them)." % (" ".join(group), c.name))
            if c.__dict__.get("default"):
                s.comment("Peridigm's 'default': a mesh block no other entry of Blocks names.")
            if material is not None:
                s.set("Material", material)
            if damage is not None:
                s.set("Damage model", damage)
            if h is not None and common is None and (disc_h is None or h[0] != disc_h):
                s.set("Horizon", h[0])
            if h is None and disc_h is None and c not in no_horizon:
                no_horizon.add(c)
                self.cannot(c, "no Horizon for this block (and none in Discretization)", path=c.path() + "/Horizon")
            if self.disc_type in ("Box", "Cylinder shell"):
                if dn != "block_1":
                    self.cannot(c.children.get("Block Names") or c,
                                "PdQuickGrid makes one block, block_1, of every point: '%s'" % dn)
            elif self.disc_type == "Exodus":
                self.exodus_block(dn, c, s)
            elif self.disc_type in ("Gmsh", "Text file"):
                m = re.fullmatch(r"block_(\d+)", dn)
                if not m:
                    self.cannot(c.children.get("Block Names"), "the block '%s' is not named block_N, so its "
                                "%s is unknown" % (dn, "Gmsh physical group" if self.disc_type == "Gmsh"
                                                   else "block number in the text file"))
                else:
                    self.block_ids[dn] = m.group(1)
                    s.set("Material ids", m.group(1), ("Exodus %s: Gmsh volume physical group %s."
                                                       if self.disc_type == "Gmsh" else
                                                       "%s: block %s of the text file.") % (dn, m.group(1)))
        out.items.insert(len([i for i in out.items if i[0] == "comment"]),
                         ["set", "Names", ", ".join(dn for _, dn, _, _, _ in blocks)])
        self.peridigm_blocks = [(c, [dn], material, damage, h) for c, dn, material, damage, h in blocks]

    def exodus_block(self, name, c, s):
        """Blocks/NAME/Material ids: the id of the Exodus element block that
        Peridigm's block NAME is (its name in the file, or block_ID)."""
        names = self.exodus_names
        if name in names.blocks:
            i = names.blocks[name]
        else:
            m = re.fullmatch(r"block_(\d+)", name)
            if names.error is None or not m:
                self.cannot(c.children.get("Block Names") or c, "the mesh has no element block '%s'%s" % (
                    name, "; it has " + ", ".join(sorted(names.blocks)) if names.blocks else ""))
                return
            i = int(m.group(1))
        self.block_ids[name] = str(i)
        s.set("Material ids", str(i), "Exodus element block %s ('%s')." % (i, name))

    def mesh_block_names(self):
        """The names (block_N) of the blocks of the discretization, or None
        where the converter cannot list them."""
        if self.disc_type in ("Box", "Cylinder shell"):
            return ["block_1"]
        ids = None
        if self.disc_type == "Exodus":
            names = self.exodus_names
            return None if names.error else sorted(names.blocks, key=lambda n: names.blocks[n])
        if self.disc_type == "Gmsh" and self.args.mesh:
            ids = gmsh_volume_cells(self.args.mesh)[1]
        elif self.disc_type == "Text file" and getattr(self, "point_file", None):
            ids = text_file_blocks(self.point_file)
        if ids is None:
            return None
        return ["block_%d" % i for i in sorted(ids)]

    def expand_default(self, b, entries):
        """Peridigm's Block Names 'default' stands for every mesh block no
        other entry names (Peridigm's DefaultBlocks regression test): replaced
        by those blocks, from the mesh."""
        for c, dnames, _, _, _ in entries:
            c.mesh_blocks = list(dnames)
        defaults = [e for e in entries if "default" in e[1]]
        if not defaults:
            return entries
        if len(defaults) > 1:
            self.cannot(defaults[1][0].children.get("Block Names"), "'default' in two entries ('%s' and '%s')"
                        % (defaults[0][0].name, defaults[1][0].name))
            return entries
        c = defaults[0][0]
        named = set(dn for e in entries for dn in e[1] if dn != "default")
        mesh = self.mesh_block_names()
        if mesh is None:
            self.cannot(c.children.get("Block Names"), "'default' (every mesh block no other entry names): the "
                        "converter lists a mesh's blocks from --mesh or the Text File only; name the blocks "
                        "(block_1 block_2 ...)")
            return [e for e in entries if e[0] is not c]
        rest = [n for n in mesh if n not in named]
        if not rest:
            self.warn(c.children.get("Block Names"), "'default' names no block: every mesh block (%s) is named by "
                      "another entry" % " ".join(mesh))
        c.default = True
        out = []
        for e in entries:
            if e[0] is c:
                names = [n for n in e[1] if n != "default"] + rest
                c.mesh_blocks = names
                out.append((e[0], names, e[2], e[3], e[4]))
            else:
                out.append(e)
        return out

    # Regions (node sets) -----------------------------------------------------

    def region_for_node_set(self, name, node):
        """The PeriDeal region name for a Peridigm node set, or None."""
        if name == "All":
            return "All"
        if name in self.regions:
            return name
        if "," in name:
            self.cannot(node, "a node set name with a comma cannot be a PeriDeal region name")
            return None
        spec = self.node_set_specs.get(name)
        if spec is None:
            if name in self.node_set_defs and self.disc_type in ("Exodus", "Text file", "Box"):
                return self.point_numbers_region(name, self.node_set_defs[name])
            if name in self.node_set_defs:
                d = self.node_set_defs[name]
                self.cannot(node, "the node set '%s' is given by node numbers (a list, or a file of them: '%s', "
                            "line %d): PeriDeal's "
                            "regions are geometric; give it with --node-set '%s=box:...' or "
                            "'expression:...'" % (name, d.value.strip(), d.line, name))
            elif self.disc_type == "Exodus":
                names = self.exodus_names
                if names.error is None and name not in names.node_sets:
                    self.cannot(node, "the mesh has no node set '%s'; it has %s" % (
                        name, ", ".join(sorted(names.node_sets)) or "none"))
                    return None
                self.add_region(name, "Node set", [("Node set", name)], "The Exodus mesh's node set '%s'." % name)
                return name
            elif getattr(self, "peridigm_disc", None) == "Exodus":
                self.cannot(node, "the Exodus node set '%s' is not known to PeriDeal: give it with "
                            "--node-set '%s=box:X0,Y0,Z0:X1,Y1,Z1' (or expression:..., group:N)" % (name, name))
            elif getattr(self, "peridigm_disc", None) == "PdQuickGrid":
                self.cannot(node, "no node set '%s': PdQuickGrid defines only 'All'; give it with "
                            "--node-set '%s=box:...' or 'expression:...'" % (name, name))
            else:
                self.cannot(node, "the node set '%s' is not known to PeriDeal: give it with --node-set "
                            "'%s=box:...' or 'expression:...'" % (name, name))
            return None
        kind, _, rest = spec.partition(":")
        if kind == "box":
            corners = rest.split(":")
            if len(corners) != 2 or any(len(x.split(",")) != 3 or not all(is_number(v) for v in x.split(","))
                                        for x in corners):
                raise InputError("--node-set %s=%s: expected box:X0,Y0,Z0:X1,Y1,Z1" % (name, spec))
            self.add_region(name, "Box", [("Lower corner", corners[0]), ("Upper corner", corners[1])])
        elif kind == "expression":
            self.add_region(name, "Expression", [("Expression", rest)])
        elif kind == "group":
            parts = rest.split(":")
            if not parts[0].isdigit() or (len(parts) > 1 and parts[1] not in ("2", "3")):
                raise InputError("--node-set %s=%s: expected group:N or group:N:DIM" % (name, spec))
            self.add_region(name, "Physical group", [("Physical group", parts[0]),
                                                     ("Physical group dimension", parts[1] if len(parts) > 1 else "3")])
        else:
            raise InputError("--node-set %s=%s: SPEC is box:..., expression:... or group:..."
                     % (name, spec))
        return name

    def point_numbers_region(self, name, d):
        """A node set the deck gives by Peridigm's point numbers (a list, or
        a file of them): a region of Type Point numbers (an Exodus mesh's
        element ids, a Text file's points in the order of its lines, a
        PdQuickGrid box's points x fastest, as PeriDeal's Box numbers them)."""
        text = d.value.strip()
        if text and all(re.fullmatch(r"[+-]?\d+", t) for t in text.split()):
            self.add_region(name, "Point numbers", [("Point numbers", " ".join(text.split()))],
                            "Peridigm's node set '%s': its point numbers (line %d of the deck)." % (name, d.line))
            return name
        here = os.path.join(os.path.dirname(os.path.abspath(self.deck)), text)
        path = os.path.normpath(here) if not os.path.isabs(text) and os.path.lexists(here) else text
        problem = regular_file_problem(path)
        if problem:
            self.cannot(d, "the node set file '%s' of '%s': %s" % (text, name, problem))
            return None
        self.input_files.append(("a node set file", path))
        self.add_region(name, "Point numbers", [("Point number file", path)],
                        "Peridigm's node set '%s': the point numbers in '%s'." % (name, text))
        return name

    def add_region(self, name, rtype, keys, comment=None):
        if name not in self.regions:
            self.regions[name] = (rtype, keys, comment)
            self.region_order.append(name)

    def emit_regions(self):
        if not self.regions:
            return
        r = self.prm.sub("Discretization").sub("Regions")
        r.comment("Peridigm's node sets (and blocks of compute classes) as regions.")
        r.set("Names", ", ".join(self.region_order))
        for name in self.region_order:
            rtype, keys, comment = self.regions[name]
            s = r.sub(name)
            if comment:
                s.comment(comment)
            elif name in self.node_set_specs:
                s.comment("--node-set %s=%s" % (name, self.node_set_specs[name]))
            s.set("Type", rtype)
            for k, v in keys:
                s.set(k, v)

    # Boundary conditions ----------------------------------------------------

    BC_TYPES = {
        "Initial Velocity": "Initial velocity",
        "Initial Displacement": "Initial displacement",
        "Prescribed Displacement": "Prescribed displacement",
        "Prescribed Velocity": "Prescribed velocity",
        "Body Force": "Body force",
    }

    def conditions_section(self, b):
        # Components some Prescribed Displacement holds (free_translations()).
        self.held_components = set()
        if b is None:
            return
        out = self.prm.sub("Boundary conditions")
        self.from_comment(out, b)
        for c in b.children.values():
            if not c.is_list():
                c.used = True
                self.node_set_defs[c.name] = c
                beside = os.path.join(os.path.dirname(os.path.abspath(self.deck)), c.value.strip())
                if c.value.strip() and os.path.lexists(beside):
                    self.input_files.append(("the node set file", beside))
        names = []
        uses_rnd = False
        for c in b.children.values():
            if not c.is_list():
                continue
            c.used = True
            if self.bad_name(c):
                continue
            btype = self.text(c, "Type", required=True)
            node_set = self.text(c, "Node Set", required=True)
            coord = self.text(c, "Coordinate")
            value_node = self.child(c, "Value")
            if btype is None:
                self.skip(c)
                continue
            if btype not in self.BC_TYPES:
                self.cannot(c.children["Type"], "the condition type '%s' has no PeriDeal equivalent (PeriDeal "
                            "has %s; temperature is one field, Temperature/Function)"
                            % (btype, ", ".join("'%s'" % k for k in self.BC_TYPES)))
                self.skip(c)
                continue
            if coord is None or coord.lower() not in ("x", "y", "z"):
                self.cannot(c.children.get("Coordinate") or c, "Coordinate must be x, y or z, got '%s'" % coord,
                            path=c.path() + "/Coordinate")
                self.skip(c)
                continue
            region = self.region_for_node_set(node_set, c.children["Node Set"]) if node_set else None
            expr = None
            if value_node is None or value_node.is_list():
                self.cannot(c, "'Value' is missing", path=c.path() + "/Value")
            else:
                try:
                    expr = translate_expression(value_node.value)
                except ExprError as e:
                    self.cannot(value_node, "the function '%s': %s" % (value_node.value.strip(), e))
            self.leftovers(c)
            if region is None or expr is None:
                continue
            s = out.sub(c.name)
            self.from_comment(s, c)
            s.set("Type", self.BC_TYPES[btype])
            s.set("Region", region)
            s.set("Component", coord.lower(), "Peridigm's Coordinate.")
            if expr.replace(" ", "") != value_node.value.strip().replace(" ", ""):
                s.comment("Peridigm: %s" % value_node.value.strip())
            if btype == "Prescribed Displacement":
                expr = self.displacement_from_start(expr, value_node, s)
                self.held_components.add(coord.lower())
            s.set("Value", expr)
            if "rnd(" in expr:
                uses_rnd = True
                s.set("Random seed", str(self.args.seed),
                      "rnd(a): uniform in [-a, a], by seed, component and point: not Peridigm's\n"
                      "random numbers (statistically alike, not point by point).")
            names.append(c.name)
        out.items.insert(len([i for i in out.items if i[0] == "comment"]), ["set", "Names", ", ".join(names)])
        if not names:
            self.prm.items = [i for i in self.prm.items if not (i[0] == "sub" and i[1] is out)]
        return uses_rnd

    def start_time(self):
        """The first solver's Initial Time (0 if not given), read without
        marking it (the solver section converts it)."""
        solvers = sorted([n for n in self.root.children if re.fullmatch(r"Solver\d*", n)],
                         key=lambda n: int(n[6:] or 0))
        if not solvers or not self.root.children[solvers[0]].is_list():
            return 0.0
        t0 = self.root.children[solvers[0]].children.get("Initial Time")
        return float(t0.value) if t0 is not None and not t0.is_list() and is_number(t0.value) else 0.0

    SAMPLE_POINTS = ((0.0, 0.0, 0.0), (1.0, 2.0, 3.0), (-0.7, 0.3, 1.9), (1e-3, -2e-3, 5e-4), (25.0, -40.0, 13.0))

    def displacement_from_start(self, expr, node, s):
        """Peridigm applies a Prescribed Displacement f as increments f(t_n+1)
        - f(t_n) from the displacement at the start (its DirichletIncrementBC,
        none at t = t0), so u(t) = u(t0) + f(t) - f(t0); PeriDeal sets u =
        f(t). Where f(t0) is not 0 the value becomes f(t) - f(t0). But where
        the increment is 0 (Peridigm's BoundaryCondition::evaluateMuParser: "a
        constant prescribed displacement") Peridigm takes the value minus the
        present displacement as the increment, u = f: an f that does not
        depend on t is the displacement itself, written as it is."""
        if not re.search(r"\bt\b", expr) and "rnd(" not in expr:
            if expr.strip() not in ("0", "0.0"):
                s.comment("Constant in time: Peridigm applies a prescribed displacement whose increment\n"
                          "f(t_n+1) - f(t_n) is 0 as u = f (the value, not an increment), as PeriDeal.")
            return expr
        t0 = self.start_time()
        try:
            zero = all(evaluate_expression(expr, {"x": x, "y": y, "z": z, "t": t0}) == 0
                       for x, y, z in self.SAMPLE_POINTS)
        except ExprError:
            zero = False  # rnd(), or a value the samples cannot evaluate: written as the difference
        if zero:
            return expr
        at_start = re.sub(r"\bt\b", "(%s)" % fmt(t0), expr)
        s.comment("Peridigm applies a Prescribed Displacement as increments f(t_n+1) - f(t_n)\n"
                  "from the start (u = 0 there), so u(t) = f(t) - f(%s); PeriDeal sets u = its\n"
                  "Value: written as f(t) - f(%s), f(%s) not being 0." % (fmt(t0), fmt(t0), fmt(t0)))
        self.warn(node, "the prescribed displacement is not 0 at the start (t = %s): Peridigm applies it as increments "
                  "from u = 0 (u = f(t) - f(%s)), PeriDeal sets u = Value: written as (%s) - (%s)"
                  % (fmt(t0), fmt(t0), expr, at_start))
        return "(%s) - (%s)" % (expr, at_start)

    # Contact ----------------------------------------------------------------

    CONTACT = {"Short Range Force": "Short range force",
               "Time Dependent Short Range Force": "Time dependent short range force"}

    def contact_section(self, c):
        if c is None:
            return
        out = self.prm.sub("Contact")
        models = self.prm.sub("Contact models")
        self.from_comment(out, c)
        self.from_comment(models, c.children.get("Models") or c, "'Contact/Models'")
        self.child(c, "Verbose")  # Peridigm's contact search report: dropped, as every Verbose
        v = self.number(c, "Search Radius")
        if v is not None:
            out.set("Search radius", v)
        v = self.number(c, "Search Frequency", integer=True)
        if v is not None:
            out.set("Search frequency", v)
        ms = self.child(c, "Models")
        mnames = []
        if ms is not None:
            for m in self.list_entries(ms, "a contact model is a list"):
                model = self.text(m, "Contact Model", required=True)
                if model not in self.CONTACT:
                    if model is not None:
                        self.cannot(m.children["Contact Model"], "the contact model '%s' has no PeriDeal "
                                    "equivalent" % model)
                    self.skip(m)
                    continue
                s = models.sub(m.name)
                self.from_comment(s, m)
                s.set("Model", self.CONTACT[model])
                for key, pkey in (("Contact Radius", "Contact radius"), ("Friction Coefficient", "Friction coefficient"),
                                  ("Horizon", "Horizon")):
                    val = self.number(m, key, required=(key == "Contact Radius"))
                    if val is not None:
                        s.set(pkey, val)
                k = self.child(m, "Spring Constant")
                if k is None:
                    self.cannot(m, "'Spring Constant' is missing", path=m.path() + "/Spring Constant")
                elif model == "Short Range Force":
                    if is_number(k.value):
                        s.set("Spring constant", num(k.value))
                    else:
                        self.cannot(k, "not a number")
                else:
                    try:
                        s.set("Spring constant", translate_expression(k.value, ("t",)))
                    except ExprError as e:
                        self.cannot(k, "the function '%s': %s" % (k.value.strip(), e))
                self.leftovers(m)
                mnames.append(m.name)
        models.items.insert(len([i for i in models.items if i[0] == "comment"]), ["set", "Names", ", ".join(mnames)])
        inter = self.child(c, "Interactions")
        inames = []
        if inter is not None:
            isub = out.sub("Interactions")
            for i in self.list_entries(inter, "an interaction is a list"):
                model = self.text(i, "Contact Model", required=True)
                if i.name in ("General Contact", "Self Contact"):
                    if model is not None:
                        out.set("General contact model" if i.name == "General Contact" else "Self contact model",
                                model)
                    self.leftovers(i)
                    continue
                first = self.text(i, "First Block", required=True)
                second = self.text(i, "Second Block", required=True)
                self.leftovers(i)
                pf, ps = self.block_map.get(first), self.block_map.get(second)
                for dn, pn in ((first, pf), (second, ps)):
                    if dn is not None and pn is None:
                        self.cannot(i, "no block '%s' in Blocks" % dn, path=i.path())
                if None in (pf, ps, model):
                    continue
                s = isub.sub(i.name)
                self.from_comment(s, i)
                s.set("First block", pf)
                s.set("Second block", ps)
                s.set("Contact model", model)
                inames.append(i.name)
            isub.items.insert(0, ["set", "Names", ", ".join(inames)])
        self.leftovers(c)

    # Compute classes --------------------------------------------------------

    COMPUTE_VARIABLES = {
        "Force": ("Force x", "Force y", "Force z"),
        "Displacement": ("Displacement x", "Displacement y", "Displacement z"),
        "Velocity": ("Velocity x", "Velocity y", "Velocity z"),
        "Model_Coordinates": ("Position x", "Position y", "Position z"),
        "Damage": ("Damage",),
        "Kinetic_Energy": ("Kinetic energy",),
    }
    OPERATIONS = {"Sum": "Sum", "Minimum": "Minimum", "Maximum": "Maximum", "Min": "Minimum", "Max": "Maximum"}

    def computes_section(self, cc):
        if cc is None:
            return
        out = self.prm.sub("Computes")
        self.from_comment(out, cc)
        names = []
        for c in self.list_entries(cc, "a compute class is a list", essential=False):
            cls = self.text(c, "Compute Class", required=True, essential=False)
            label = self.text(c, "Output Label", required=True, essential=False)
            if label:
                self.labels.add(label)
            self.child(c, "Verbose")
            if cls == "Nearest_Point_Data":
                xyz = [self.number(c, a, required=True, essential=False) for a in "XYZ"]
                var = self.text(c, "Variable", required=True, essential=False)
                self.leftovers(c, essential=False)
                if var is not None and var not in self.COMPUTE_VARIABLES:
                    self.cannot(c.children["Variable"], "the variable '%s' is not a PeriDeal compute variable"
                                % var, essential=False)
                    continue
                if None in xyz or var is None or label is None:
                    continue
                pvars = self.COMPUTE_VARIABLES[var]
                for i, pv in enumerate(pvars):
                    name = label if len(pvars) == 1 else "%s_%s" % (label, "xyz"[i])
                    s = out.sub(name)
                    if i == 0:
                        self.from_comment(s, c)
                        s.comment("Peridigm's Nearest_Point_Data: the value at the point nearest to X, Y, Z.")
                    s.set("Region", "All")
                    s.set("Variable", pv)
                    s.set("Operation", "Nearest point")
                    s.set("Location", ",".join(xyz))
                    names.append(name)
                continue
            if cls not in ("Block_Data", "Node_Set_Data"):
                if cls is not None:
                    self.cannot(c.children["Compute Class"], "the compute class '%s' has no PeriDeal compute"
                                % cls, essential=False)
                self.skip(c)
                continue
            op = self.text(c, "Calculation Type", required=True, essential=False)
            var = self.text(c, "Variable", required=True, essential=False)
            region = None
            if cls == "Block_Data":
                block = self.text(c, "Block", required=True, essential=False)
                if block is not None:
                    region = self.region_for_block(block, c.children["Block"])
            else:
                ns = self.text(c, "Node Set", required=True, essential=False)
                if ns is not None:
                    region = self.region_for_node_set(ns, c.children["Node Set"])
            self.leftovers(c, essential=False)
            if op not in self.OPERATIONS:
                if op is not None:
                    self.cannot(c.children["Calculation Type"], "Calculation Type '%s': PeriDeal has Sum, "
                                "Minimum, Maximum (and Mean)" % op, essential=False)
                continue
            if var not in self.COMPUTE_VARIABLES:
                if var is not None:
                    self.cannot(c.children["Variable"], "the variable '%s' is not a PeriDeal compute variable"
                                % var, essential=False)
                continue
            if region is None or label is None:
                continue
            pvars = self.COMPUTE_VARIABLES[var]
            for i, pv in enumerate(pvars):
                name = label if len(pvars) == 1 else "%s_%s" % (label, "xyz"[i])
                s = out.sub(name)
                if i == 0:
                    self.from_comment(s, c)
                s.set("Region", region)
                s.set("Variable", pv)
                s.set("Operation", self.OPERATIONS[op])
                names.append(name)
        out.items.insert(len([i for i in out.items if i[0] == "comment"]), ["set", "Names", ", ".join(names)])
        if not names:
            self.prm.items = [i for i in self.prm.items if not (i[0] == "sub" and i[1] is out)]

    def region_for_block(self, block, node):
        entries = getattr(self, "peridigm_blocks", [])
        if self.disc_type in ("Box", "Cylinder shell") and block == "block_1":
            return "All"
        if block in self.block_ids and self.disc_type == "Exodus":
            self.add_region(block, "Element block", [("Element block", block)],
                            "Exodus element block %s ('%s')." % (self.block_ids[block], block))
            return block
        if block in self.block_ids:
            name = block
            self.add_region(name, "Physical group", [("Physical group", self.block_ids[block]),
                                                     ("Physical group dimension", "3")],
                            ("Exodus %s: the cells of Gmsh volume physical group %s." if self.disc_type == "Gmsh" else
                             "%s: the points of block (material id) %s of the text file.")
                            % (block, self.block_ids[block]))
            return name
        if len(entries) == 1 and block in entries[0][1] and len(entries[0][1]) == 1:
            return "All"
        self.cannot(node, "no block '%s' PeriDeal can make a region of" % block, essential=False)
        return None

    # Solver -----------------------------------------------------------------

    def solver_section(self, s, out=None, start=None):
        """Solver (out None), or a later solver into its Solver stages entry out,
        starting where the one before ended (start, if known). Returns the end
        time (None if unknown); self.solver_type becomes its PeriDeal Type."""
        stage = out is not None
        if not stage:
            out = self.prm.sub("Solver")
        self.solver_type = None
        self.time_step_segments = []
        self.from_comment(out, s)
        self.child(s, "Verbose")
        self.solver_path_keys(s)
        t0 = self.number(s, "Initial Time")
        t1 = self.number(s, "Final Time")
        if stage:
            # A stage has no Initial time: it starts where the solver before it ended.
            if t0 is not None and start is not None and abs(float(t0) - float(start)) > 1e-12 * max(1.0, abs(float(start))):
                self.warn(s.children["Initial Time"], "Initial Time %s is not the end of the solver before (%s): "
                          "PeriDeal starts a stage where the one before ended" % (t0, start))
            t0 = start
        kinds = [k for k in ("Verlet", "QuasiStatic", "NOXQuasiStatic", "Implicit") if k in s.children]
        if len(kinds) != 1:
            self.cannot(s, "one of Verlet, QuasiStatic, NOXQuasiStatic, Implicit is needed, found %s"
                        % (", ".join(kinds) or "none"), path=s.path())
            self.leftovers(s)
            return None
        kind = kinds[0]
        k = self.child(s, kind)
        self.solver_type = {"Verlet": "Verlet", "QuasiStatic": "QuasiStatic", "NOXQuasiStatic": "QuasiStatic",
                            "Implicit": "Newmark"}[kind]
        if stage and t0 is not None:
            out.comment("Starts at t = %s, where the solver before it ends." % t0)
        free = sorted(set("xyz") - getattr(self, "held_components", set()))
        if self.solver_type == "QuasiStatic" and free:
            # No Prescribed Displacement along these: the body is free to
            # translate along them (the rotations depend on the node sets).
            out.comment("No Prescribed Displacement acts along %s: the body is free to translate\n"
                        "that way. Peridigm solves it when the loads balance, and its answer may\n"
                        "carry any rigid part; PeriDeal projects the free motions out (its\n"
                        "displacement has no rigid part) and refuses loads that push along them."
                        % ", ".join(free))
            self.warn(s, "no Prescribed Displacement acts along %s, so the body may translate freely that way: "
                      "PeriDeal solves it with the free motions projected out (no rigid part; Peridigm's answer "
                      "may carry one) and refuses loads that push along them" % ", ".join(free))
        if kind == "Verlet":
            out.set("Type", "Verlet", "Peridigm's Verlet: explicit velocity Verlet.")
            if t0 is not None and not stage:
                out.set("Initial time", t0)
            if t1 is not None:
                out.set("Final time", t1)
            else:
                self.cannot(s, "'Final Time' is missing", path=s.path() + "/Final Time")
            v = out.sub("Verlet")
            dt = self.number(k, "Fixed dt")
            sf = self.number(k, "Safety Factor")
            if dt is not None and float(dt) <= 0:
                self.cannot(k.children["Fixed dt"], "must be positive, got %s" % dt)
                dt = None
            if dt is not None and sf is not None:
                # Peridigm multiplies a Fixed dt by the Safety Factor too
                # (Peridigm.cpp, executeExplicit); PeriDeal's Safety factor
                # applies to its own estimate only.
                step = float(dt) * float(sf)
                v.set("Fixed dt", repr(step), "Peridigm's Fixed dt %s times its Safety Factor %s: Peridigm scales a\n"
                      "fixed step by the safety factor too, PeriDeal does not." % (dt, sf))
                if float(sf) != 1:
                    self.warn(k.children["Safety Factor"], "Peridigm multiplies Fixed dt by the Safety Factor: written "
                              "as Fixed dt = %s x %s = %r (PeriDeal's Safety factor scales its own stable estimate "
                              "only)" % (dt, sf, step))
                dt = repr(step)
            elif dt is not None:
                v.set("Fixed dt", dt)
            if sf is not None and dt is None:
                v.set("Safety factor", sf)
                v.comment("TRAP: the stable time step is estimated by each code its own way:\n"
                          "the same Safety factor may give a different step (and step count);\n"
                          "and Peridigm takes floor(T/dt) steps of dt, PeriDeal ceil(T/dt) steps\n"
                          "shortened to end at the Final time.")
            start_t = float(t0) if t0 is not None else 0.0
            if dt is not None and t1 is not None:
                span = float(t1) - start_t
                n = math.floor(span / float(dt))  # Peridigm's count (Peridigm.cpp, executeExplicit)
                n_perideal = math.ceil(span / float(dt) - 1e-9)  # PeriDeal's (verlet.cc)
                if n >= 1 and n != n_perideal:
                    end = start_t + n * float(dt)
                    out.set("Final time", repr(end),
                            "Peridigm's Final Time %s is not a whole number of Fixed dt %s from %s:\n"
                            "Peridigm takes floor(T/dt) = %d steps of dt and stops at %r;\n"
                            "PeriDeal would take ceil(T/dt) = %d shortened steps to %s. This Final time\n"
                            "gives Peridigm's %d steps of dt."
                            % (t1, dt, fmt(start_t), n, end, n_perideal, t1, n))
                    self.warn(s.children.get("Final Time") or s, "Final Time %s is not a whole number of Fixed dt %s "
                              "from %s: Peridigm takes floor(T/dt) = %d steps of dt and ends at %r, PeriDeal would "
                              "take %d shortened steps to %s: written as Final time = %r (Peridigm's steps)"
                              % (t1, dt, fmt(start_t), n, end, n_perideal, t1, end), path=s.path() + "/Final Time")
                    t1 = repr(end)
                elif n < 1:
                    self.warn(s.children.get("Final Time") or s, "the run (%r) is shorter than Fixed dt %s: Peridigm "
                              "takes no step; PeriDeal takes one shortened step" % (span, dt),
                              path=s.path() + "/Final Time")
            if dt is None and sf is None:
                self.warn(k, "neither Fixed dt nor Safety Factor: PeriDeal's default Safety factor 0.8 applies")
        elif kind in ("QuasiStatic", "NOXQuasiStatic"):
            out.set("Type", "QuasiStatic", "Peridigm's %s: Newton's method per load step." % kind)
            out.sub("QuasiStatic").set("Velocity", "load step",
                                       "Peridigm's velocity of a load step, (u_n - u_(n-1)) / dt, in the output\n"
                                       "(PeriDeal's default, rest, writes 0).")
            if t0 is not None and not stage:
                out.set("Initial time", t0)
            if t1 is not None:
                out.set("Final time", t1)
            steps_node = self.child(k, "Time Steps")
            n = self.number(k, "Number of Load Steps", required=steps_node is None, integer=True)
            if n is not None:
                out.set("Number of steps", n)
            imp = out.sub("Implicit")
            if steps_node is not None and n is not None:
                self.cannot(steps_node, "both Number of Load Steps and Time Steps: give one")
            elif steps_node is not None:
                t1 = self.time_steps(steps_node, out, imp, s, stage, t0, t1)
            v = self.number(k, "Absolute Tolerance")
            if v is not None:
                imp.set("Absolute tolerance", v)
            v = self.number(k, "Relative Tolerance")
            if v is not None:
                imp.set("Tolerance", v)
            for key in ("Maximum Solver Iterations", "Max Solver Iterations"):
                v = self.number(k, key, integer=True)
                if v is not None:
                    imp.set("Maximum Newton iterations", v)
            ls = self.boolean(k, "Perform Line Search")
            if ls is not None:
                imp.set("Line search", "true" if ls else "false")
            jac = self.text(k, "Jacobian Operator")
            if jac is not None:
                imp.set("Jacobian", "Matrix free" if jac.lower().startswith("matrix") else "Assembled",
                        "Peridigm's Jacobian Operator '%s'." % jac)
            self.child(k, "Verbose")
            self.leftovers(k, essential=False, reason="a solver setting PeriDeal's Newton solver does not have "
                           "(doc/implicit.md); PeriDeal's default applies")
        else:  # Implicit: Newmark
            out.set("Type", "Newmark", "Peridigm's Implicit: Newmark-beta.\n"
                    "TRAP: Peridigm starts Newmark from a = 0; PeriDeal from the acceleration\n"
                    "of the initial forces: the first step differs (by a factor 2 in its\n"
                    "displacement under a load applied at once).")
            self.warn(k, "Peridigm's Newmark starts from a = 0, PeriDeal's from the acceleration of the initial forces: "
                      "the first step differs (a factor 2 under a load applied at once)")
            dt = self.number(k, "Fixed dt", required=True)
            if dt is not None and float(dt) <= 0:
                self.cannot(k.children["Fixed dt"], "must be positive, got %s" % dt)
                dt = None
            if t0 is not None and not stage:
                out.set("Initial time", t0)
            if t1 is not None:
                out.set("Final time", t1)
            if dt is not None and t1 is not None:
                # Peridigm's count: floor((Final Time - Initial Time) / Fixed dt)
                # steps of Fixed dt (Peridigm.cpp, executeImplicit).
                span = float(t1) - float(t0 or 0)
                steps = math.floor(span / float(dt))
                end = float(t0 or 0) + steps * float(dt)
                if steps >= 1 and abs(end - float(t1)) > 1e-12 * max(abs(span), abs(float(t1))):
                    out.set("Final time", repr(end),
                            "Peridigm's Final Time %s is not a whole number of Fixed dt %s: Peridigm takes\n"
                            "floor(T/dt) = %d steps of dt and stops at %r." % (t1, dt, steps, end))
                    self.warn(s.children.get("Final Time") or s, "Final Time %s is not a whole number of Fixed dt %s "
                              "from %s: Peridigm's Implicit takes floor(T/dt) = %d steps of dt and ends at %r: written "
                              "as Final time = %r and Number of steps = %d" % (t1, dt, fmt(float(t0 or 0)), steps, end,
                                                                             end, steps), path=s.path() + "/Final Time")
                    t1 = repr(end)
                if steps < 1:
                    self.cannot(s.children.get("Final Time") or s, "the run (%r) is shorter than Fixed dt %s: Peridigm "
                                "takes no step" % (span, dt), path=s.path() + "/Final Time")
                    steps = 1
                out.set("Number of steps", str(steps), "floor((Final Time - Initial Time) / Fixed dt), Peridigm's count.")
            imp = out.sub("Implicit")
            for key, pkey in (("Beta", "Newmark beta"), ("Gamma", "Newmark gamma"),
                              ("Absolute Tolerance", "Absolute tolerance"), ("Relative Tolerance", "Tolerance")):
                v = self.number(k, key)
                if v is not None:
                    imp.set(pkey, v)
            v = self.number(k, "Maximum Solver Iterations", integer=True)
            if v is not None:
                imp.set("Maximum Newton iterations", v)
            self.child(k, "Verbose")
            self.leftovers(k, essential=False, reason="a solver setting PeriDeal's Newton solver does not have "
                           "(doc/implicit.md); PeriDeal's default applies")
        self.leftovers(k)
        self.leftovers(s)
        return t1

    def time_steps(self, node, out, imp, s, stage, t0, t1):
        """Peridigm's QuasiStatic 'Time Steps' (the load-step times, from the
        first to the last, Peridigm.cpp executeQuasiStatic): the first run of
        equal steps is this solver (Initial time, Final time, Number of steps),
        each further run a Solver stage with the same Implicit settings
        (self.time_step_segments, made into stages by segment_stages). Returns
        the end time."""
        try:
            times = [float(v) for v in node.value.replace(",", " ").split()]
        except (AttributeError, ValueError):
            times = []
        if len(times) < 2 or any(not math.isfinite(t) for t in times) or \
                any(b <= a for a, b in zip(times, times[1:])):
            self.cannot(node, "Time Steps must be two or more increasing times, got '%s'"
                        % (node.value.strip() if node.value else ""))
            return t1
        runs = []  # [start, end, steps] of equal steps
        for a, b in zip(times, times[1:]):
            if runs and abs((b - a) - (runs[-1][1] - runs[-1][0]) / runs[-1][2]) <= 1e-12 * max(abs(a), abs(b), b - a):
                runs[-1][1] = b
                runs[-1][2] += 1
            else:
                runs.append([a, b, 1])
        start = float(t0) if t0 is not None else None
        if stage and start is not None and abs(times[0] - start) > 1e-12 * max(1.0, abs(start)):
            self.warn(node, "the first of the Time Steps, %s, is not where the solver before ended (%s): PeriDeal "
                      "starts a stage there" % (fmt(times[0]), fmt(start)))
        elif not stage:
            out.set("Initial time", fmt(times[0]), "The first of Peridigm's Time Steps.")
        if t1 is not None and abs(float(t1) - times[-1]) > 1e-12 * max(1.0, abs(times[-1])):
            self.warn(s.children.get("Final Time"), "Final Time %s is not the last of the Time Steps (%s): Peridigm "
                      "loads to the last of the Time Steps, and so does the converter" % (t1, fmt(times[-1])),
                      path=s.path() + "/Final Time")
        out.set("Final time", fmt(runs[0][1]))
        out.set("Number of steps", str(runs[0][2]),
                "Peridigm's Time Steps (%s):\n%d load steps in %d run%s of equal steps; this solver takes the first "
                "(to %s)%s." % (node.value.strip(), len(times) - 1, len(runs), "s" if len(runs) > 1 else "",
                                fmt(runs[0][1]), ",\nSolver stages the others" if len(runs) > 1 else ""))
        self.time_step_segments = [(fmt(b), str(n), imp, s.name) for _, b, n in runs[1:]]
        return fmt(times[-1])

    def segment_stages(self, stages, name, segments):
        """The Solver stages NAME_steps2, NAME_steps3, ... of a Time Steps
        list's further runs of equal load steps; returns their names."""
        import copy
        names = []
        for i, (end, n, imp, solver) in enumerate(segments, 2):
            stage_name = "%s_steps%d" % (name, i)
            st = stages.sub(stage_name)
            st.comment("Peridigm's Time Steps of %s: run %d of equal load steps." % (solver, i))
            st.set("Type", "QuasiStatic")
            st.sub("QuasiStatic").set("Velocity", "load step")
            st.set("Final time", end)
            st.set("Number of steps", n)
            st.items.append(("sub", copy.deepcopy(imp)))
            names.append(stage_name)
        return names

    SOLVER_PATH_KEYS = {
        "Peridigm Preconditioner": "the preconditioner of Peridigm's matrix-free NOX solves (None, Full Tangent, "
                                   "Block 3x3): it changes the path of the solver, not the answer; PeriDeal's "
                                   "Newton solver has its own (Solver/Implicit, doc/implicit.md)",
        "Initialize Predictor From Previous Solver": "Peridigm's first guess of a solver from the one before it: it "
                                                     "changes the path of the solver, not the answer; a PeriDeal "
                                                     "stage starts from the state the one before left",
    }

    def solver_path_keys(self, s):
        """The keys of a Peridigm solver (or of its Verlet, QuasiStatic, ...
        list) that change only how the solver gets to the answer: named, not
        essential."""
        for node in [s] + [c for c in s.children.values() if c.is_list()]:
            for key, why in self.SOLVER_PATH_KEYS.items():
                c = self.child(node, key)
                if c is not None:
                    self.cannot(c, why, essential=False)

    # Output -----------------------------------------------------------------

    FIELDS = {
        "Displacement": "Displacement", "Velocity": "Velocity", "Acceleration": "Acceleration",
        "Force_Density": "Force density", "Damage": "Damage", "Dilatation": "Dilatation",
        "Weighted_Volume": "Weighted volume", "Proc_Num": "Rank", "Number_Of_Neighbors": "Number of neighbors",
        "Deformation_Gradient": "Deformation gradient", "Cauchy_Stress": "Cauchy stress",
        "Von_Mises_Stress": "Von Mises stress", "Equivalent_Plastic_Strain": "Equivalent plastic strain",
        "Temperature": "Temperature", "Block_Id": "Block",
    }
    GLOBALS = {
        "Global_Kinetic_Energy": "the globals CSV's kinetic_energy",
        "Global_Strain_Energy": "the globals CSV's strain_energy",
        "Kinetic_Energy": None, "Strain_Energy": None,
        "Global_Linear_Momentum": ("Momentum", "Global_Linear_Momentum"),
        "Global_Angular_Momentum": ("Angular momentum", "Global_Angular_Momentum"),
    }

    # PeriDeal's fields of some models only (pd_app refuses a field no block's
    # model has: postprocess.cc; the models that declare them: lps.cc,
    # correspondence.cc, elastic_plastic.cc, elastic_plastic_correspondence.cc).
    MODEL_FIELDS = {
        "Dilatation": ("LPS",),
        "Weighted_Volume": ("LPS",),
        "Deformation_Gradient": ("Elastic correspondence", "Elastic plastic correspondence"),
        "Cauchy_Stress": ("Elastic correspondence", "Elastic plastic correspondence"),
        "Von_Mises_Stress": ("Elastic correspondence", "Elastic plastic correspondence"),
        "Equivalent_Plastic_Strain": ("Elastic plastic", "Elastic plastic correspondence"),
    }

    def field_of_these_blocks(self, v):
        """False (and named) for an output variable pd_app would refuse: a
        field of models no block has, Temperature without a temperature field
        (the converter writes none); a warning when some blocks lack it."""
        if v.name == "Temperature":
            self.cannot(v, "PeriDeal writes Temperature only with a temperature field (Temperature/Function), "
                        "which the converter does not write: dropped, pd_app would refuse it", essential=False)
            return False
        owners = self.MODEL_FIELDS.get(v.name)
        if owners is None or not getattr(self, "peridigm_blocks", None):
            return True
        models = {}
        for name, material, _, _ in self.block_horizons():
            models.setdefault(self.materials.get(material), []).append(name)
        models.pop(None, None)
        what = " or ".join(owners)
        if not models or any(m in owners for m in models):
            others = sorted(n for m, names in models.items() if m not in owners for n in names)
            if others:
                self.warn(v, "PeriDeal's '%s' is a field of %s blocks only; blocks %s have none"
                          % (self.FIELDS[v.name], what, ", ".join(others)))
            return True
        self.cannot(v, "PeriDeal's '%s' is a field of %s only, and no block is (%s): dropped, pd_app would "
                    "refuse it" % (self.FIELDS[v.name], what, "; ".join(
                        "%s: %s" % (m, ", ".join(n)) for m, n in sorted(models.items()))), essential=False)
        return False

    def output_sections(self, sections):
        if not sections:
            return
        out = self.prm.sub("Output")
        exodus_output = False
        field_done = False
        globals_frequency = None
        extra_computes = []
        for o in sections:
            self.from_comment(out, o)
            ftype = self.text(o, "Output File Type", essential=False)
            if ftype is None or ftype.lower() == "exodusii":
                # Peridigm's default, Exodus II: the same file, variables named as Peridigm names them.
                exodus_output = True
            elif ftype != "VTU":
                out.comment("Peridigm's %s becomes VTU files (.pvd, .pvtu, .vtu) for ParaView." % ftype)
            self.child(o, "Output Format")
            self.child(o, "Parallel Write")
            base = self.text(o, "Output Filename", essential=False)
            freq = self.number(o, "Output Frequency", integer=True, essential=False)
            for key in ("Initial Output Step", "Final Output Step"):
                c = self.child(o, key)
                if c is not None:
                    self.cannot(c, "PeriDeal writes every Frequency steps from the first to the last",
                                essential=False)
            variables = self.child(o, "Output Variables")
            if variables is None:
                variables = self.child(o, "Material Output Fields")  # pre-1.0 decks
            fields, wanted_globals = [], []
            if variables is not None:
                for v in variables.children.values():
                    v.used = True
                    if v.is_list():
                        self.cannot(v, "a list where an output variable was expected", essential=False)
                        continue
                    on = v.value.strip().lower() in ("true", "1", "yes")
                    if not on:
                        continue
                    if v.name in self.FIELDS:
                        if self.FIELDS[v.name] not in fields and self.field_of_these_blocks(v):
                            fields.append(self.FIELDS[v.name])
                    elif v.name in self.GLOBALS:
                        wanted_globals.append(v)
                    elif v.name in self.labels:
                        pass  # a compute class's column of the globals CSV
                    else:
                        self.cannot(v, "PeriDeal has no output field '%s'" % v.name, essential=False)
            for g in wanted_globals:
                what = self.GLOBALS[g.name]
                if what is None:
                    self.cannot(g, "per-point energies are not written; the globals CSV has the totals",
                                essential=False)
                elif isinstance(what, tuple):
                    extra_computes.append((what, g))
            self.leftovers(o, essential=False, reason="an output setting PeriDeal does not have")
            if fields or not wanted_globals:
                if field_done:
                    self.cannot(o, "PeriDeal writes one set of field files per run", essential=False)
                    continue
                field_done = True
                if base:
                    out.set("Base name", base)
                if freq is not None:
                    out.set("Frequency", freq)
                out.set("Variables", ", ".join(fields))
            else:
                # An output of global values only: the globals CSV's rows.
                if base and not field_done:
                    out.set("Base name", base)
                if freq is not None:
                    globals_frequency = freq
        if exodus_output and field_done:
            out.set("Field format", "exodus",
                    "Peridigm's Exodus II output: <base name>.e, points as SPHERE elements, variables\n"
                    "named as Peridigm names them (DisplacementX, Force_DensityX, Damage, ...); one file\n"
                    "for all ranks (Exodus files = per rank: one per rank, as Peridigm writes them).")
        if globals_frequency is not None:
            out.set("Globals frequency", globals_frequency,
                    "The globals CSV every this many steps (Peridigm's output of global variables).")
        out.set("Write globals", "true",
                "step, time, kinetic and strain energy, ... and one column per compute, every\n"
                "output step (Peridigm's Global_* variables and compute classes).")
        if extra_computes:
            comp = self.prm.sub("Computes")
            names = []
            for (variable, label), node in extra_computes:
                for a in "xyz":
                    name = "%s_%s" % (label, a)
                    s = comp.sub(name)
                    s.set("Region", "All")
                    s.set("Variable", "%s %s" % (variable, a))
                    s.set("Operation", "Sum")
                    names.append(name)
            existing = [i for i in comp.items if i[0] == "set" and i[1] == "Names"]
            if existing:
                existing[0][2] = ", ".join([n for n in existing[0][2].split(", ") if n] + names)
            else:
                comp.items.insert(0, ["set", "Names", ", ".join(names)])


# ----------------------------------------------------------------------- main


SECTION_ORDER = ("Discretization", "Materials", "Damage models", "Blocks", "Boundary conditions",
                 "Contact models", "Contact", "Computes", "Solver", "Output")


def same_file(a, b):
    """True if paths A and B are one file (through a symbolic or hard link too)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def check_output_path(output, inputs):
    """Raises InputError if OUTPUT is one of INPUTS ((what, path) pairs: the
    files the conversion reads), the same file by another name included."""
    for what, path in inputs:
        if path and same_file(output, path):
            raise InputError("-o %s is %s %s (the same file): the converter never overwrites a file it reads; "
                             "nothing written, give another output name" % (output, what, path))


def check_output_folder(path):
    """Raises InputError if PATH cannot become the parameter file: its folder
    is missing, or it is there but not a regular file (a directory, a device)."""
    target = os.path.realpath(path)
    if not os.path.isdir(os.path.dirname(target)):
        raise InputError("%s: cannot write the parameter file: the folder %s does not exist"
                         % (path, os.path.dirname(path) or "."))
    if os.path.lexists(target):
        problem = regular_file_problem(target)
        if problem:
            raise InputError("%s: cannot write the parameter file: %s" % (path, problem))


def write_whole(path, text):
    """TEXT written to PATH whole or not at all: into a temporary file in the
    same folder, renamed over PATH (over the file a symbolic link PATH points
    to) only once complete, with the old file's permissions. Raises InputError."""
    check_output_folder(path)
    target = os.path.realpath(path)
    folder = os.path.dirname(target)
    if os.path.lexists(target):
        mode = stat.S_IMODE(os.stat(target).st_mode)
    else:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    temporary = None
    try:
        fd, temporary = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(target) + ".", suffix=".tmp")
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.chmod(temporary, mode)
        os.replace(temporary, target)
        temporary = None
    except OSError as e:
        raise InputError("%s: cannot write the parameter file: %s" % (path, e.strerror or e))
    finally:
        if temporary is not None:
            try:
                os.unlink(temporary)
            except OSError:
                pass


class ArgumentParser(argparse.ArgumentParser):
    """argparse with pd_app's discipline: 'Error: ...' and exit status 1."""

    def error(self, message):
        self.print_usage(sys.stderr)
        print("Error: %s" % message, file=sys.stderr)
        sys.exit(1)


def main(argv=None):
    try:
        return convert(argv)
    except InputError as e:
        print("Error: %s" % e, file=sys.stderr)
        return 1


def convert(argv):
    ap = ArgumentParser(
        prog="peridigm_to_prm.py",
        description="Convert a Peridigm input deck (YAML or XML) into a PeriDeal parameter file.",
        epilog="Unconvertible keys are listed on standard error as DECK:LINE: cannot convert "
               "'Section/Key': reason. Exit status 1 if an essential one could not be converted. "
               "See doc/peridigm.md.")
    ap.add_argument("deck")
    ap.add_argument("-o", "--output", help="the parameter file to write (default: standard output)")
    ap.add_argument("--partial", action="store_true",
                    help="write what could be converted even if something essential could not")
    ap.add_argument("--mesh", help="a Gmsh mesh standing for the deck's Exodus mesh (hexahedra; tetrahedra, "
                    "prisms or pyramids make it Cells as points)")
    ap.add_argument("--node-set", action="append", metavar="NAME=SPEC",
                    help="a node set as a region: box:X0,Y0,Z0:X1,Y1,Z1, expression:EXPR or group:N[:DIM]")
    ap.add_argument("--seed", type=int, default=1, help="Random seed of conditions that use rnd() (default 1)")
    args = ap.parse_args(argv)

    # What the conversion reads is never its output; checked before anything is read.
    inputs = [("the deck", args.deck), ("the --mesh", args.mesh)]
    if args.output:
        check_output_path(args.output, inputs)
        check_output_folder(args.output)
    if args.mesh:
        problem = regular_file_problem(args.mesh)
        if problem:
            raise InputError("--mesh %s: cannot read the mesh: %s" % (args.mesh, problem))
    try:
        root = read_deck(args.deck)
    except DeckError as e:
        print("%s:%d: syntax error: %s" % (args.deck, e.line, e.message), file=sys.stderr)
        print("Error: %s could not be read; nothing written" % args.deck, file=sys.stderr)
        return 1

    conv = Converter(args.deck, root, args)
    try:
        conv.run()
    except (InputError, DeckError):
        raise
    except Exception as e:  # a bug of the converter: said as one line, nothing written
        print("Error: the converter failed on %s (a bug; please report it with the deck): %s: %s; nothing written"
              % (args.deck, type(e).__name__, e), file=sys.stderr)
        return 1
    if args.output:
        check_output_path(args.output, conv.input_files)
    for _, _, text, _ in sorted(conv.messages):
        print(text, file=sys.stderr)

    # The parameter file.
    fmt_lines = [
        "# PeriDeal parameter file converted from the Peridigm deck %s" % args.deck,
        "# by apps/peridigm_to_prm.py (doc/peridigm.md).",
        "#",
        "# Units: neither Peridigm nor PeriDeal has any; the numbers are copied as they",
        "# are, so the deck's consistent units (SI, CGS, ...) carry over unchanged.",
    ]
    if conv.essential_failures:
        fmt_lines.append("# INCOMPLETE (--partial): %d essential key(s) could not be converted; see"
                         % conv.essential_failures)
        fmt_lines.append("# the converter's messages.")
    body = []
    subs = {item[1].name: item[1] for item in conv.prm.items if item[0] == "sub"}
    for name in SECTION_ORDER + tuple(n for n in subs if n not in SECTION_ORDER):
        s = subs.get(name)
        if s is None:
            continue
        body.append("")
        body.append("subsection %s" % name)
        body.extend(s.render(1))
        body.append("end")
    text = "\n".join(fmt_lines + body) + "\n"

    if conv.essential_failures and not args.partial:
        print("Error: %d essential key(s) of %s could not be converted; nothing written "
              "(--partial writes the rest)" % (conv.essential_failures, args.deck), file=sys.stderr)
        return 1
    if args.output:
        write_whole(args.output, text)
    else:
        try:
            sys.stdout.write(text)
            sys.stdout.flush()
        except OSError as e:
            raise InputError("cannot write the parameter file to standard output: %s" % (e.strerror or e))
    if conv.essential_failures:
        print("Error: %d essential key(s) of %s could not be converted; the rest was written (--partial)"
              % (conv.essential_failures, args.deck), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
