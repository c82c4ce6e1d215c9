#!/usr/bin/env python3
"""The docs' key tables against the readers' key specs (issue 25 item 4; docs/developer.md
"One table per choice").

Usage: check_key_tables.py LIST_KEYS SOURCE_DIR

LIST_KEYS is the docs_list_keys program: it prints the key specs the strict pre-reader checks
(src/input/nml_source.f90), one key a line, `group key [word, word, ...]`, the words of a choice
key taken from its table. The docs hold:
  - docs/input.md, docs/mechanisms.md: `| group | key | meaning (default) |` tables; a row's
    first cell names the group (`&joint`, blank: the group of the row above), its second cell
    the keys in backticks, its third the meaning, where a choice key's words are in backticks;
  - docs/sensors.md: the &sensor `| key | meaning |` table and the `| type | ... |` table whose
    first cells are the &sensor type words.
Fails (exit 1, one line per difference) when a key is in the specs but in no table or the other
way round, or when a choice key's accepted word is missing from its row, or its row names in
backticks a word that is neither an accepted word nor a key.
"""
import re
import subprocess
import sys
from pathlib import Path

IDENTIFIER = re.compile(r'^[A-Za-z][A-Za-z0-9_]*$')


def cells(line):
    """The cells of a Markdown table row (a `\\|` is no cell border)."""
    parts = re.split(r'(?<!\\)\|', line.strip())
    return [p.strip() for p in parts[1:-1]]


def backticked(text):
    return re.findall(r'`([^`]*)`', text)


def spec_keys(list_keys):
    out = subprocess.run([list_keys], check=True, capture_output=True, text=True).stdout
    specs = {}
    for line in out.splitlines():
        if not line.strip():
            continue
        group, key, *rest = line.split(' ', 2)
        words = rest[0].strip() if rest else ''
        specs[(group, key)] = [w.strip() for w in words.split(',')] if words else []
    return specs


def table_rows(path):
    """(line number, header cells, cells) of every data row of every table of `path`."""
    header = None
    for number, line in enumerate(path.read_text(encoding='utf-8').splitlines(), 1):
        if not line.startswith('|'):
            header = None
        elif header is None:
            header = cells(line)
        elif not set(line.replace('|', '').strip()) <= set('-: '):
            yield number, header, cells(line)


def group_tables(path):
    """{(group, key): [(where, meaning), ...]} of the `| group | key | meaning |` tables."""
    rows = {}
    group = None
    for number, header, c in table_rows(path):
        if header[:2] != ['group', 'key']:
            continue
        names = re.findall(r'`&([a-z_]+)`', c[0])
        if names:
            group = names[0]
        if group is None:
            sys.exit(f'{path}:{number}: a key row before any group')
        for key in backticked(c[1]):
            rows.setdefault((group, key), []).append((f'{path.name}:{number}', c[2]))
    return rows


def sensor_tables(path):
    """The &sensor `| key | meaning |` table, and its `| type | ... |` table as the type row."""
    rows = {}
    type_words = []
    for number, header, c in table_rows(path):
        if header[0] == 'key':
            rows.setdefault(('sensor', c[0]), []).append((f'{path.name}:{number}', c[1]))
        elif header[0] == 'type':
            type_words += [(f'{path.name}:{number}', w) for w in backticked(c[0])]
    if type_words:
        rows.setdefault(('sensor', 'type'), []).append(
            (type_words[0][0], ' '.join(f'`{w}`' for _, w in type_words)))
    return rows


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    specs = spec_keys(sys.argv[1])
    docs = Path(sys.argv[2]) / 'docs'
    rows = {}
    for name in ('input.md', 'mechanisms.md'):
        for k, v in group_tables(docs / name).items():
            rows.setdefault(k, []).extend(v)
    for k, v in sensor_tables(docs / 'sensors.md').items():
        rows.setdefault(k, []).extend(v)
    all_keys = {key for _, key in specs}
    problems = []
    for group, key in sorted(specs):
        if (group, key) not in rows:
            problems.append(f'&{group} {key}: in the key specs, in no docs table')
    for group, key in sorted(rows):
        if (group, key) not in specs:
            where = rows[(group, key)][0][0]
            problems.append(f'{where}: &{group} {key}: in the docs, not in the key specs')
    checked = 0
    for (group, key), words in sorted(specs.items()):
        if not words or (group, key) not in rows:
            continue
        checked += 1
        written = {}
        for where, meaning in rows[(group, key)]:
            for w in backticked(meaning):
                if IDENTIFIER.match(w):
                    written.setdefault(w.lower(), where)
        accepted = {w.lower() for w in words}
        for w in words:
            if w.lower() not in written:
                problems.append(f'{rows[(group, key)][0][0]}: &{group} {key}: accepted word '
                                f'"{w}" is missing from the row')
        for w, where in sorted(written.items()):
            if w not in accepted and w not in all_keys:
                problems.append(f'{where}: &{group} {key}: "{w}" is no accepted word '
                                f'(the key spec takes {", ".join(words)})')
    for p in problems:
        print(p)
    print(f'{len(specs)} keys of the specs, {len(rows)} keys in the docs tables, '
          f'{checked} choice keys compared: {len(problems)} differences')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
