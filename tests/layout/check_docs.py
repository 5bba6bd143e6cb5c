#!/usr/bin/env python3
"""Checks that the repository's documentation tells the truth about the tree (run by ctest):

  - every component folder (runtime/*, tools/*, quantize/*, firmware/*, tests/*, cmake, boards)
    has a README.md;
  - the indexes list every folder: tools/README.md (tools/*), tests/README.md (tests/*),
    runtime/README.md (runtime/*);
  - tools/cli/README.md names every subcommand `tlvlink --help` prints (when given the binary);
  - relative links in Markdown files resolve, and no document points outside the repository;
  - the top README's layout block names every tools/ folder, runtime component and quantize/
    folder.

  check_docs.py REPO [TLVLINK_BINARY]
Prints one line per problem ("path: what") and exits 1 if there is any.
"""
import os
import re
import subprocess
import sys

repo = os.path.abspath(sys.argv[1])
binary = sys.argv[2] if len(sys.argv) > 2 else None
problems = []


def rel(p):
    return os.path.relpath(p, repo)


def subdirs(d):
    full = os.path.join(repo, d)
    return sorted(n for n in os.listdir(full)
                  if os.path.isdir(os.path.join(full, n)) and not n.startswith(('.', '__')))


def read(p):
    with open(os.path.join(repo, p), encoding='utf-8') as f:
        return f.read()


# 1. A README in every component folder.
folders = ['cmake', 'boards']
for top in ('runtime', 'tools', 'quantize', 'firmware', 'tests'):
    folders += [f'{top}/{n}' for n in subdirs(top) if n not in ('include', 'src')]
for d in folders:
    if not os.path.isfile(os.path.join(repo, d, 'README.md')) and d.split('/')[0] != 'tests':
        problems.append(f'{d}: no README.md')

# 2. Indexes list every folder (as `name/` or [name/](...)).
for index, top in (('tools/README.md', 'tools'), ('tests/README.md', 'tests'),
                   ('runtime/README.md', 'runtime')):
    text = read(index)
    for n in subdirs(top):
        if n == 'include':
            continue
        if not re.search(r'(`|\[|\b)' + re.escape(n) + r'/', text):
            problems.append(f'{index}: does not list {top}/{n}/')

# 3. Every CLI subcommand is documented.
if binary:
    out = subprocess.run([binary, '--help'], capture_output=True, text=True).stdout
    parts = re.split(r'^subcommands:\s*$', out, maxsplit=1, flags=re.M | re.I)
    section = parts[1] if len(parts) == 2 else ''
    commands = re.findall(r'^\s{2}([a-z][a-z0-9-]*)\s', section, re.M)
    if not commands:
        problems.append(f'{binary}: --help lists no subcommands')
    cli_doc = read('tools/cli/README.md')
    for c in commands:
        if not re.search(r'`(tlvlink )?' + re.escape(c) + r'[` ]', cli_doc):
            problems.append(f'tools/cli/README.md: does not document `tlvlink {c}`')

# 4. Links resolve and stay inside the repository.
link = re.compile(r'\]\(([^)\s]+)\)')
for root, dirs, files in os.walk(repo):
    dirs[:] = [d for d in dirs if not d.startswith('.') and d not in ('build', 'node_modules')]
    for name in files:
        if not name.endswith('.md'):
            continue
        path = os.path.join(root, name)
        text = open(path, encoding='utf-8').read()
        if '../shared/' in text or '/work/' in text:
            problems.append(f'{rel(path)}: points outside the repository (../shared/ or /work/)')
        for target in link.findall(text):
            if re.match(r'^[a-z]+:', target) or target.startswith('#'):
                continue
            target = target.split('#', 1)[0]
            resolved = os.path.normpath(os.path.join(root, target))
            if not resolved.startswith(repo + os.sep) and resolved != repo:
                problems.append(f'{rel(path)}: link {target} leaves the repository')
            elif not os.path.exists(resolved):
                problems.append(f'{rel(path)}: broken link {target}')

# 5. The top README's layout block lists what is there (it had fallen behind the tree).
m = re.search(r'^## Layout\n\n```\n(.*?)```', read('README.md'), re.S | re.M)
block = m.group(1) if m else ''
if not m:
    problems.append('README.md: no "## Layout" block')
for n in subdirs('tools'):
    if not re.search(r'^tools/' + re.escape(n) + r'/', block, re.M):
        problems.append(f'README.md: the layout block does not list tools/{n}/')
for top in ('runtime', 'quantize'):
    for n in subdirs(top):
        if n != 'include' and not re.search(r'\b' + re.escape(n) + r'\b', block):
            problems.append(f'README.md: the layout block does not name {top}/{n}')

for p in problems:
    print(p)
print(f'check_docs: {len(folders)} folders, {len(problems)} problem(s)')
sys.exit(1 if problems else 0)
