#!/usr/bin/env python3
"""Checks the components' boundaries (run by ctest): every header in runtime/<c>/src is guarded
by TLVLINK_<C>_PRIVATE, every header in a src/ folder of quantize/ and tools/ by the guard its
component defines (HOST_GUARDS below), and including it from outside the component fails to
compile with the guard's #error (the compiler gets every include path of the three floors).

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
# The host components' src/ folders and the guard each defines while compiling itself (its
# CMakeLists): the folder name, except where two folders share a name.
HOST_GUARDS = {
    'quantize/src': 'TLVLINK_QUANTIZE_PRIVATE',
    'quantize/writer/src': 'TLVLINK_MODEL_WRITER_PRIVATE',
    'tools/quantize/src': 'TLVLINK_QUANTIZE_PIPELINE_PRIVATE',
    'tools/io/src': 'TLVLINK_IO_PRIVATE',
}
includes = []
for top in ('runtime', 'quantize', 'tools'):
    for d in sorted(glob.glob(os.path.join(repo, top, '**', ''), recursive=True)):
        if os.path.basename(os.path.dirname(d)) in ('include', 'src'):
            includes += ['-I', d]
includes += ['-I', os.path.join(repo, 'runtime', 'include')]


def guard_of(rel):
    """The guard a private header must carry, or None if `rel` is no private header."""
    parts = rel.split(os.sep)
    if parts[0] == 'runtime':
        return f'TLVLINK_{parts[1].upper()}_PRIVATE' if parts[2] == 'src' else None
    for folder, guard in HOST_GUARDS.items():
        if rel.startswith(folder + os.sep):
            return guard
    if parts[0] == 'tools' and len(parts) > 3 and parts[2] == 'src':
        return f'TLVLINK_{parts[1].upper()}_PRIVATE'
    return None


headers = []
for top in ('runtime', 'quantize', 'tools'):
    for h in sorted(glob.glob(os.path.join(repo, top, '**', 'src', '**', '*.h'), recursive=True)):
        if guard_of(os.path.relpath(h, repo)):
            headers.append(h)
for h in headers:
    rel = os.path.relpath(h, repo)
    component = os.path.dirname(rel).split(os.sep + 'src')[0]
    guard = guard_of(rel)
    text = open(h, encoding='utf-8').read()
    m = re.search(r'#ifndef\s+' + guard + r'\b[^\n]*\n\s*#error\s+(?:\\\n\s*)?"([^"]*)"', text)
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
