#!/usr/bin/env python3
"""Checks the runtime's component boundaries (run by ctest): every header in runtime/<c>/src is
guarded by TLVLINK_<C>_PRIVATE, and including it from outside the component fails to compile
with the guard's #error (the compiler gets every include path, so nothing else can be missing).

  check_private_headers.py REPO CXX
Prints one line per problem and exits 1 if there is any.
"""
import glob
import os
import re
import subprocess
import sys
import tempfile

repo, cxx = os.path.abspath(sys.argv[1]), sys.argv[2]
problems = []
includes = []
for d in sorted(glob.glob(os.path.join(repo, 'runtime', '*'))):
    for sub in ('include', 'src'):
        if os.path.isdir(os.path.join(d, sub)):
            includes += ['-I', os.path.join(d, sub)]
includes += ['-I', os.path.join(repo, 'runtime', 'include')]

headers = sorted(glob.glob(os.path.join(repo, 'runtime', '*', 'src', '**', '*.h'), recursive=True))
for h in headers:
    rel = os.path.relpath(h, repo)
    component = rel.split(os.sep)[1]
    guard = f'TLVLINK_{component.upper()}_PRIVATE'
    text = open(h, encoding='utf-8').read()
    m = re.search(r'#ifndef\s+' + guard + r'\b[^\n]*\n\s*#error\s+"([^"]*)"', text)
    if not m:
        problems.append(f'{rel}: no "#ifndef {guard}" + #error "..." guard')
        continue
    with tempfile.NamedTemporaryFile('w', suffix='.cc', delete=False) as f:
        f.write(f'#include "{h}"\n')
        probe = f.name
    try:
        r = subprocess.run([cxx, '-std=c++20', '-fsyntax-only', *includes, probe],
                           capture_output=True, text=True)
    finally:
        os.unlink(probe)
    if r.returncode == 0:
        problems.append(f'{rel}: compiles when included from outside {component}')
    elif m.group(1) not in r.stderr:
        problems.append(f'{rel}: fails to compile, but not at its guard')
    elif 'internal' not in m.group(1):
        problems.append(f'{rel}: the guard does not say the header is internal')

for p in problems:
    print(p)
print(f'check_private_headers: {len(headers)} internal headers, {len(problems)} problem(s)')
sys.exit(1 if problems else 0)
