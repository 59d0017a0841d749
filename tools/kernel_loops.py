#!/usr/bin/env python3
"""Reads the generated code of plume's hot kernels as a build compiles them.

    python3 tools/kernel_loops.py BUILD_DIR [--show KERNEL] [--no-calls] [--max-stack N]

Compiles tools/kernel_loops.cpp with the flags BUILD_DIR uses for the collision benchmark
(its instruction sets, -O3, -ffp-contract=off, ...), then prints for each kernel loop
k_<kernel>_x<width>: the instructions of the hot loop (the body between the loop's backward
branch and its target; cold paths the compiler moved out of it are not counted), how many
of them reference the stack (spills, reloads, aggregates left in memory) and how many are
calls. --show prints one loop's code. The exit status is 1 when a wide loop (x4 and up)
calls out of line (--no-calls; CI checks this) or has more stack references than N
(--max-stack).

Needs objdump (binutils) and the build's compiler; BUILD_DIR must be configured with
PLUME_BUILD_BENCH=ON (its build.ninja holds the command line this reuses).
"""
import argparse
import os
import re
import shlex
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def compile_command(build_dir, source, obj):
    """The build's command for bench_ray_cast.cpp, retargeted at source -> obj."""
    out = subprocess.run(['ninja', '-C', build_dir, '-t', 'commands', 'bench/plume_bench_collision'],
                         capture_output=True, text=True, check=True).stdout
    line = next((l for l in out.splitlines() if 'bench_ray_cast.cpp' in l and ' -c ' in l), None)
    if line is None:
        sys.exit(f'{build_dir}: no compile command for bench_ray_cast.cpp (PLUME_BUILD_BENCH=ON?)')
    args, skip = [], 0
    for a in shlex.split(line):
        if skip:
            skip -= 1
            continue
        if a in ('-MD',):
            continue
        if a in ('-MT', '-MF', '-o', '-c'):
            skip = 1
            continue
        args.append(a)
    return args + ['-Wno-missing-declarations', '-c', source, '-o', obj]


def loops(obj):
    """{function: [(address, mnemonic, operands)] of its hot loop}."""
    dis = subprocess.run(['objdump', '-d', '--no-show-raw-insn', obj], capture_output=True,
                         text=True, check=True).stdout
    funcs, name = {}, None
    for l in dis.splitlines():
        m = re.match(r'[0-9a-f]+ <(k_\w+)>:', l)
        if m:
            name = m.group(1)
            funcs[name] = []
            continue
        if not l.strip():
            name = None
            continue
        m = re.match(r'\s*([0-9a-f]+):\s+(\S+)\s*(.*)', l)
        if name and m:
            funcs[name].append((int(m.group(1), 16), m.group(2), m.group(3)))
    result = {}
    for f, ins in funcs.items():
        best = None
        for a, op, args in ins:  # the widest backward conditional branch: the kernel's loop
            m = re.match(r'([0-9a-f]+) ', args)
            if op.startswith('j') and op != 'jmp' and m:
                t = int(m.group(1), 16)
                if t < a and (best is None or a - t > best[1] - best[0]):
                    best = (t, a)
        result[f] = [x for x in ins if best and best[0] <= x[0] <= best[1]]
    return result


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument('build_dir')
    p.add_argument('--show', metavar='KERNEL', help='print the loop of k_KERNEL (e.g. ray_sphere_x8)')
    p.add_argument('--no-calls', action='store_true', help='fail if a wide loop calls out of line')
    p.add_argument('--max-stack', type=int, metavar='N', help='fail if a wide loop has more')
    a = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        obj = os.path.join(tmp, 'kernel_loops.o')
        cmd = compile_command(a.build_dir, os.path.join(ROOT, 'tools', 'kernel_loops.cpp'), obj)
        subprocess.run(cmd, check=True, cwd=a.build_dir)
        found = loops(obj)
    if not found:
        sys.exit('no k_ functions found')
    bad, shown = [], None
    print(f'{"kernel":24s} {"instructions":>12s} {"stack refs":>10s} {"calls":>5s}')
    for f in sorted(found, key=lambda f: (f.rsplit('_x', 1)[0], int(f.rsplit('_x', 1)[1]))):
        body = found[f]
        stack = sum(bool(re.search(r'\(%r[sb]p\)', x[2])) for x in body)
        calls = sum(x[1].startswith('call') for x in body)
        print(f'{f[2:]:24s} {len(body):12d} {stack:10d} {calls:5d}')
        wide = not f.endswith('_x1')
        if wide and ((a.no_calls and calls) or (a.max_stack is not None and stack > a.max_stack)):
            bad.append(f[2:])
        if a.show and f == 'k_' + a.show:
            shown = body
    if a.show:
        if shown is None:
            sys.exit(f'no kernel {a.show}')
        for addr, op, args in shown:
            print(f'{addr:6x}  {op:10s} {args}')
    if bad:
        print('over the limit:', ' '.join(bad))
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
