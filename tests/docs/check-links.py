#!/usr/bin/env python3
"""Check that every relative link in README.md and docs/**/*.md resolves to a file or folder in the tree.

Run from anywhere: python3 tests/docs/check-links.py [ROOT]. Prints each broken link as
FILE:LINE: target, and exits 1 if there is any. Not registered with ctest: a helper for whoever
edits the docs. Anchors (#...) are checked for .md targets against their headings (GitHub's slug rule,
simplified: lower case, punctuation but '-' and '_' dropped, spaces to '-').
"""
import os
import re
import sys

root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..', '..'))
link = re.compile(r'(?<!!)\[[^\]]*\]\(([^)\s]+)\)')
fence = re.compile(r'^\s*```')


def slugs(path):
    out = set()
    in_code = False
    for line in open(path, encoding='utf-8'):
        if fence.match(line):
            in_code = not in_code
            continue
        if not in_code and line.startswith('#'):
            text = line.lstrip('#').strip().lower()
            text = re.sub(r'[^\w\- ]', '', text)
            out.add(text.replace(' ', '-'))
    return out


files = [os.path.join(root, 'README.md')]
for dirpath, _, names in os.walk(os.path.join(root, 'docs')):
    files += [os.path.join(dirpath, n) for n in names if n.endswith('.md')]

broken = 0
checked = 0
for path in sorted(files):
    in_code = False
    for number, line in enumerate(open(path, encoding='utf-8'), 1):
        if fence.match(line):
            in_code = not in_code
            continue
        if in_code:
            continue
        for target in link.findall(line):
            if re.match(r'^[a-z][a-z0-9+.-]*:', target):  # http:, mailto:, ...
                continue
            checked += 1
            file_part, _, anchor = target.partition('#')
            resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
            problem = None
            if not os.path.exists(resolved):
                problem = 'no such file'
            elif anchor and resolved.endswith('.md') and anchor not in slugs(resolved):
                problem = 'no such heading'
            if problem:
                broken += 1
                print(f'{os.path.relpath(path, root)}:{number}: {target}: {problem}')
print(f'{checked} relative links checked in {len(files)} files, {broken} broken', file=sys.stderr)
sys.exit(1 if broken else 0)
