#!/usr/bin/env python3
"""Fail on a file reference of the documentation that names no file of the
repository (test input.doc_references).

    check_doc_references.py REPOSITORY_ROOT

Read: README.md and doc/**/*.md, and the sources (source/, include/, apps/,
tests/, bench/, the top CMakeLists.txt) for the doc/ pages they cite, in
comments and parameter strings alike. In a Markdown page, outside fenced code
blocks:
  - a link or image [text](target): relative to the page (URLs, mail
    addresses and same-page anchors are not files; an anchor after a path is
    dropped);
  - a code span that is a path: relative to the repository root when its first
    part is a top-level entry of the repository (`source/x.cc`, `doc/models.md`,
    `tests/...`), relative to the page when it starts with ./ or ../, relative
    to source/ or include/perideal/ when its first part is one of their
    folders (`solver/tangent.h`);
  - a file name in the text (`x.md`, `x.cc`, `x.h`, `x.py`, `x.prm`, ...):
    relative to the page, the root, source/ or include/perideal/, or else the
    name of some file of the repository.
A reference must name an existing file or folder inside the repository; a
path naming a test by its files' stem (`tests/physics/viscoelastic_sls` for
viscoelastic_sls.cc and .output) counts. Placeholders (NAME, SCENE, npN, *,
<base>) and what a run or build writes (build/, output/) are no files. Each
missing one is printed as PAGE:LINE: ...; the exit code is 1 if any is.
"""

import os
import re
import sys
from pathlib import Path

EXTENSIONS = ('md', 'cc', 'h', 'py', 'prm', 'in', 'msh', 'geo', 'sh', 'cmake', 'xml', 'yaml', 'output')
PLACEHOLDER = re.compile(r'[*<>{}$]|(?<![A-Za-z])(NAME|SCENE|SERIES|LABEL|BASE|MODEL)(?![A-Za-z])|rRES|npN|(?<![A-Za-z])my_')
GENERATED = ('build', 'output')
URL = re.compile(r'^[A-Za-z][A-Za-z0-9+.-]*:')
LINK = re.compile(r'!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\)')
CODE_SPAN = re.compile(r'`([^`\n]+(?:\n[^`\n]+)?)`')
PATH_TOKEN = re.compile(r'[\w.\-/]+')
PROSE_FILE = re.compile(r'(?<![\w/.\-])((?:[\w.\-]+/)*[\w\-]+(?:\.[\w\-]+)*\.(?:%s))(?![\w/])' % '|'.join(EXTENSIONS))
DOC_CITATION = re.compile(r'(?<![\w/.])doc/[\w.\-/]*[\w/]')
SOURCE_SUFFIXES = ('.cc', '.h', '.py', '.txt', '.cmake', '.sh', '.prm', '.in')


class Repository:
    def __init__(self, root):
        self.root = root.resolve()
        self.files = set()
        for folder, dirs, names in os.walk(self.root):
            here = Path(folder)
            dirs[:] = [d for d in dirs if not d.startswith('.') and not (here == self.root and d.startswith('build'))]
            for name in names + dirs:
                self.files.add((here / name).relative_to(self.root).as_posix())
        self.top = {f for f in self.files if '/' not in f}
        self.modules = {f.split('/')[-1] for f in self.files if re.fullmatch(r'(source|include/perideal)/[\w]+', f)}
        self.basenames = {f.split('/')[-1] for f in self.files}

    def exists(self, path):
        """An existing file or folder inside the repository (a path's stem counts)."""
        try:
            relative = path.resolve().relative_to(self.root).as_posix()
        except ValueError:
            return False  # outside the repository
        if relative in self.files or relative == '.':
            return True
        return any(f.startswith(relative + '.') for f in self.files if '/' in relative)

    def suffix_exists(self, token):
        """Some file of the repository is named token (or ends with /token)."""
        token = token.rstrip('/')
        if '/' not in token:
            return token in self.basenames
        return any(f == token or f.endswith('/' + token) for f in self.files)


def split_fences(text):
    """The text outside fenced code blocks and the text inside them, each with
    the other blanked (line numbers kept)."""
    outside, inside, fenced = [], [], False
    for line in text.split('\n'):
        if line.lstrip().startswith('```'):
            fenced = not fenced
            line = ''
        outside.append('' if fenced else line)
        inside.append(line if fenced else '')
    return '\n'.join(outside), '\n'.join(inside)


def check_link(repo, page, target):
    if URL.match(target) or target.startswith('#'):
        return True
    target = target.split('#')[0]
    return repo.exists(page.parent / target)


def check_code_span(repo, page, token):
    """None if the span is no path, else whether it names a file."""
    if not PATH_TOKEN.fullmatch(token) or PLACEHOLDER.search(token) or token.startswith('/'):
        return None
    first = token.split('/')[0]
    if first in GENERATED and '/' in token:
        return None
    if token.startswith('./') or token.startswith('../'):
        return repo.exists(page.parent / token)
    if '/' in token and first in repo.top:
        return repo.exists(repo.root / token)
    if '/' in token and first in repo.modules:
        return any(repo.exists(repo.root / base / token) for base in ('source', 'include/perideal'))
    return None


def check_prose_file(repo, page, token):
    if PLACEHOLDER.search(token):
        return True
    bases = (page.parent, repo.root, repo.root / 'source', repo.root / 'include/perideal')
    return any(repo.exists(base / token) for base in bases) or repo.suffix_exists(token)


def blank(match):
    """A match replaced by spaces, its newlines kept (line numbers hold)."""
    return re.sub(r'[^\n]', ' ', match.group(0))


def check_page(repo, page, report):
    count = 0
    text, code_blocks = split_fences(page.read_text(encoding='utf-8'))

    def line_of(match):
        return text.count('\n', 0, match.start()) + 1

    for match in LINK.finditer(text):
        count += 1
        if not check_link(repo, page, match.group(1)):
            report(page, line_of(match), 'link', match.group(1))
    prose = LINK.sub(blank, text)
    for match in CODE_SPAN.finditer(prose):
        token = ' '.join(match.group(1).split()).rstrip('.,;:')
        ok = check_code_span(repo, page, token)
        if ok is not None:
            count += 1
            if not ok:
                report(page, line_of(match), 'path', token)
    prose = CODE_SPAN.sub(blank, prose)
    for match in PROSE_FILE.finditer(prose):
        count += 1
        if not check_prose_file(repo, page, match.group(1)):
            report(page, line_of(match), 'file name', match.group(1))
    return count + check_citations(repo, page, code_blocks, report)


def check_citations(repo, path, text, report):
    """The doc/ pages a text cites anywhere (comments, strings, code blocks)."""
    count = 0
    for number, line in enumerate(text.split('\n'), 1):
        for match in DOC_CITATION.finditer(line):
            token = match.group(0).rstrip('.')
            if PLACEHOLDER.search(token):
                continue
            count += 1
            if not repo.exists(repo.root / token):
                report(path, number, 'doc citation', token)
    return count


def sources(repo):
    yield repo.root / 'CMakeLists.txt'
    for folder in ('source', 'include', 'apps', 'tests', 'bench'):
        for path in sorted((repo.root / folder).rglob('*')):
            if path.is_file() and (path.suffix in SOURCE_SUFFIXES or path.name == 'CMakeLists.txt'):
                yield path


def main():
    if len(sys.argv) != 2:
        sys.exit('usage: check_doc_references.py REPOSITORY_ROOT')
    repo = Repository(Path(sys.argv[1]))
    missing = []

    def report(path, number, kind, token):
        missing.append(f'{path.relative_to(repo.root)}:{number}: {kind} {token!r} names no file of the repository')

    pages = [repo.root / 'README.md'] + sorted((repo.root / 'doc').rglob('*.md'))
    count = sum(check_page(repo, page, report) for page in pages)
    code = list(sources(repo))
    count += sum(check_citations(repo, path, path.read_text(encoding='utf-8', errors='replace'), report)
                 for path in code)
    for line in missing:
        print(line)
    print(f'{count} file references checked in {len(pages)} pages and {len(code)} sources: {len(missing)} missing')
    return 1 if missing else 0


if __name__ == '__main__':
    sys.exit(main())
