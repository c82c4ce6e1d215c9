#!/usr/bin/env python3
"""Every section citation in the sources resolves to a heading that exists (issue 25, item 1).

The sources cite the manual by file and section name: `docs/batch.md "Job arrays"`,
`README "Quick start"`, `theory.md 4.5`, and inside docs/ also `[faults.md](faults.md) "Faults"`.
A section moved or renamed without its citations leaves a reader at a dead end, so this test reads
every text file of src, driver, include, tests, postprocess, input, examples, cmake, docs, .ci,
CMakeLists.txt and README.md and checks each citation:

- `README "S"`, `README.md "S"` (a comma may follow the file name): a heading of README.md whose
  text starts with S ("Quick start" matches "## Quick start (Debian 12, from a fresh clone)");
- `docs/F.md "S"`, `F.md "S"` and `[F.md](F.md) "S"` for F a file of docs/: a heading of docs/F.md
  starting with S;
- `theory.md N` or `theory.md N.M` (also `theory.md section N`, `theory.md 5.6-5.8`): a numbered
  heading "## N." or "### N.M" of docs/theory.md;
- every relative Markdown link `](path)` of README.md and docs/*.md names a file that exists, and
  its `#anchor`, if any, a heading of that file (GitHub's slug).

Also: the command CI runs (the last line of .ci/run) is one of the README's fenced command
lines, the quick start's test command, so that the README's "tests from zero" is what CI runs.

A citation may wrap onto the next comment line (`!>`, `!`, `#`, `//`, `*` are skipped). Exit 1
listing every citation that does not resolve, with file and line; also when fewer citations than
a floor are found (the patterns would otherwise be able to match nothing and pass).

    check_citations.py SOURCE_DIR
"""
import re
import sys
from pathlib import Path

SCAN = ['src', 'driver', 'include', 'tests', 'postprocess', 'input', 'examples', 'cmake', 'docs',
        '.ci']
TOP = ['CMakeLists.txt', 'README.md']
SUFFIXES = {'.f90', '.c', '.h', '.py', '.cmake', '.txt', '.nml', '.md', '.sh', '.geo', '.in',
            '.toml', ''}
# a comment break inside a citation: new line, blanks and one comment marker
BREAK = r'(?:\s*\n\s*(?:!>|!|#|//|\*)?\s*|\s+)'
FLOOR = 60


def headings(path):
    """Heading texts of a Markdown file, outside code fences."""
    out, fence = [], False
    for line in path.read_text(encoding='utf-8').split('\n'):
        if line.startswith('```'):
            fence = not fence
        elif not fence and re.match(r'#{1,6} ', line):
            out.append(line.lstrip('#').strip())
    return out


def slug(text):
    """GitHub's anchor of a heading: lower case, punctuation dropped, blanks to hyphens."""
    text = text.lower().replace('`', '')
    text = re.sub(r'[^\w\- ]', '', text)
    return text.replace(' ', '-')


def line_of(text, pos):
    return text.count('\n', 0, pos) + 1


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = Path(sys.argv[1]).resolve()
    docs = {p.name: headings(p) for p in (root / 'docs').glob('*.md')}
    readme = headings(root / 'README.md')
    theory_numbers = set()
    for h in docs.get('theory.md', []):
        m = re.match(r'(\d+(?:\.\d+)?)\.?\s', h)
        if m:
            theory_numbers.add(m.group(1))

    files = [root / t for t in TOP]
    for d in SCAN:
        for p in sorted((root / d).rglob('*')):
            if p.is_file() and (p.suffix in SUFFIXES or p.name == 'CMakeLists.txt') \
                    and 'build' not in p.relative_to(root).parts[:1]:
                files.append(p)

    failures, found = [], 0
    docnames = '|'.join(re.escape(n) for n in sorted(docs, key=len, reverse=True))
    sec = r'"((?:[^"\n]|\n\s*(?:!>|!|#|//|\*)?\s*){2,120}?)"'
    pat_readme = re.compile(r'\bREADME(?:\.md)?,?' + BREAK + sec)
    pat_doc = re.compile(r'(?:\[(?:docs/)?(' + docnames + r')\]\((?:docs/)?\1\)|(?<![\w/.-])(?:docs/)?('
                         + docnames + r')),?' + BREAK + sec)
    pat_theory = re.compile(r'\btheory\.md,?' + BREAK + r'(?:sections?' + BREAK + r')?(\d+(?:\.\d+)?)')
    for path in files:
        try:
            text = path.read_text(encoding='utf-8')
        except (UnicodeDecodeError, OSError):
            continue
        rel = path.relative_to(root)
        if path.resolve() == Path(__file__).resolve():
            continue
        for m in pat_readme.finditer(text):
            found += 1
            cited = re.sub(r'\s*\n\s*(?:!>|!|#|//|\*)?\s*', ' ', m.group(1)).strip()
            if not any(h.startswith(cited) for h in readme):
                failures.append(f'{rel}:{line_of(text, m.start())}: README "{cited}": no heading '
                                'of README.md starts so')
        for m in pat_doc.finditer(text):
            found += 1
            name = m.group(1) or m.group(2)
            cited = re.sub(r'\s*\n\s*(?:!>|!|#|//|\*)?\s*', ' ', m.group(3)).strip()
            if not any(h.startswith(cited) for h in docs[name]):
                failures.append(f'{rel}:{line_of(text, m.start())}: docs/{name} "{cited}": no '
                                f'heading of docs/{name} starts so')
        for m in pat_theory.finditer(text):
            found += 1
            number = m.group(1)
            if number not in theory_numbers:
                failures.append(f'{rel}:{line_of(text, m.start())}: theory.md {number}: no such '
                                'numbered section in docs/theory.md')
        if path.suffix == '.md' and (path.parent == root / 'docs' or path == root / 'README.md'):
            fence = False
            for n, line in enumerate(text.split('\n'), 1):
                if line.startswith('```'):
                    fence = not fence
                if fence:
                    continue
                for link in re.findall(r'\]\(([\w./#-]+)\)', line):
                    if re.match(r'[a-z]+:', link):
                        continue
                    target, _, anchor = link.partition('#')
                    found += 1
                    dest = (path.parent / target).resolve() if target else path
                    if not dest.exists():
                        failures.append(f'{rel}:{n}: link ({link}): {target} does not exist')
                    elif anchor and dest.suffix == '.md':
                        if anchor not in {slug(h) for h in headings(dest)}:
                            failures.append(f'{rel}:{n}: link ({link}): no heading #{anchor} in '
                                            f'{target or path.name}')
    ci = [l.strip() for l in (root / '.ci' / 'run').read_text().split('\n') if l.strip()][-1]
    readme_lines = [l.strip() for l in (root / 'README.md').read_text(encoding='utf-8').split('\n')]
    if ci not in readme_lines:
        failures.append(f'.ci/run runs "{ci}", which is not a command line of README.md')
    print(f'{len(files)} files, {found} citations and links checked, {len(failures)} unresolved')
    for f in failures:
        print('  ' + f)
    if found < FLOOR:
        print(f'only {found} citations found, fewer than {FLOOR}: the patterns match nothing?')
        sys.exit(1)
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
