#!/usr/bin/env python3
"""docs/developer.md lists every Fortran module of src/ (issue 25, item 3).

Reference: the source tree itself. Every src/**/*.f90 holds one `module NAME` or
`submodule (PARENT[:ANCESTOR]) NAME`; the "Module map" section of docs/developer.md must have a
line naming both the file (relative to src/, in backticks) and NAME (in backticks), and every file that
section names must exist. Exit 1 listing the modules missing and the stale lines.

    check_module_map.py SOURCE_DIR
"""
import re
import sys
from pathlib import Path


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = Path(sys.argv[1])
    text = (root / 'docs' / 'developer.md').read_text(encoding='utf-8')
    start = text.find('\n## Module map')
    if start < 0:
        sys.exit('docs/developer.md has no "## Module map" section')
    end = text.find('\n## ', start + 1)
    section = text[start:end if end > 0 else len(text)]
    lines = section.split('\n')
    problems, count = [], 0
    for path in sorted((root / 'src').rglob('*.f90')):
        rel = path.relative_to(root / 'src').as_posix()
        source = path.read_text(encoding='utf-8')
        m = re.search(r'^\s*submodule\s*\(\s*\w+\s*(?::\s*\w+\s*)?\)\s*(\w+)|^\s*module\s+(?!procedure)(\w+)',
                      source, re.M | re.I)
        if not m:
            problems.append(f'src/{rel}: no module statement found')
            continue
        name = m.group(1) or m.group(2)
        count += 1
        if not any(f'`{rel}`' in line and f'`{name}`' in line for line in lines):
            problems.append(f'src/{rel} ({name}): no line of the Module map names both')
    for line in lines:
        for rel in re.findall(r'^- `([\w/]+\.f90)`', line):
            if not (root / 'src' / rel).is_file():
                problems.append(f'Module map names src/{rel}, which does not exist')
    print(f'{count} modules in src/, {len(problems)} problems')
    for p in problems:
        print('  ' + p)
    sys.exit(1 if problems or count == 0 else 0)


if __name__ == '__main__':
    main()
