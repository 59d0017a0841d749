#!/usr/bin/env python3
"""check_isa_leaks.py <programs or libraries...> --objects <isolated kernel objects...>

The dispatch build's safety check: in a binary built with PLUME_DISPATCH=ON, every function
that uses an instruction beyond sse2 (VEX or EVEX encoded: a mnemonic starting with 'v', a
ymm, zmm or mask register; or one of the SSSE3/SSE4/POPCNT instructions the avx2 flags also
enable, listed below) must come from one of the isolated per-ISA kernel objects, whose code runs
only after the dispatch chose that set. A function outside them with such an instruction
would fault on a CPU without AVX (the classic way: an inline function compiled with -mavx2
that the linker kept for the baseline's calls). Exit 1 and the list of offenders if any.
"""
import re
import subprocess
import sys


def symbols(obj):
    out = subprocess.run(["nm", "--defined-only", obj], capture_output=True, text=True, check=True)
    return {line.split()[-1] for line in out.stdout.splitlines() if line.strip()}


def avx_functions(binary):
    out = subprocess.run(["objdump", "-d", "--no-show-raw-insn", binary], capture_output=True,
                         text=True, check=True).stdout
    found, fn = {}, None
    head = re.compile(r"^[0-9a-f]+ <(.+)>:$")
    insn = re.compile(r"^\s+[0-9a-f]+:\s+(\S+)\s*(.*)$")
    for line in out.splitlines():
        m = head.match(line)
        if m:
            fn = m.group(1)
            continue
        m = insn.match(line)
        if not m or fn is None:
            continue
        mnem, ops = m.group(1), m.group(2)
        if (mnem.startswith("v") and mnem not in ("verr", "verw")) or mnem in (
                "popcnt", "crc32", "crc32b", "crc32w", "crc32l", "crc32q", "pcmpestri",
                "pcmpistri", "pcmpestrm", "pcmpistrm", "ptest", "pshufb", "pblendvb",
                "blendvps", "blendvpd", "roundps", "roundpd", "roundss", "roundsd") or re.search(
                r"%(ymm|zmm|k[0-7])\b", ops):
            found.setdefault(fn, f"{mnem} {ops}".strip())
    return found


def main():
    args = sys.argv[1:]
    if "--objects" not in args:
        print(__doc__)
        return 2
    k = args.index("--objects")
    binaries, objects = args[:k], args[k + 1:]
    if not binaries or not objects:
        print(__doc__)
        return 2
    allowed = set()
    for obj in objects:
        allowed |= symbols(obj)

    # Allowed: a symbol the isolation renamed (<name>.plume_<floor>_<isa>, kept through the
    # compiler's .cold / .part.N / .isra.N / .constprop.N suffixes), or a symbol of internal
    # linkage (anonymous namespace: _GLOBAL__N) defined in the kernel objects, which no other
    # translation unit can share. Not the table accessors (plume_<floor>_table_<isa>): they
    # are called on every CPU, to read which set a table is for, and must have no AVX
    # instruction.
    def ok(f):
        if re.search(r"\.plume_[a-z0-9_]+(\.|$)", f):
            return True
        base = re.sub(r"(\.(cold|part|isra|constprop)(\.\d+)?)+$", "", f)
        return "_GLOBAL__N" in base and (base in allowed or f in allowed)

    status = 0
    for binary in binaries:
        found = avx_functions(binary)
        bad = {f: i for f, i in found.items() if not ok(f)}
        if bad:
            status = 1
            print(f"{binary}: {len(bad)} functions with AVX instructions outside the kernel objects:")
            for f, i in sorted(bad.items()):
                print(f"  {f}: {i}")
        else:
            print(f"{binary}: {len(found)} functions with AVX instructions, all from the kernel objects")
    return status


if __name__ == "__main__":
    sys.exit(main())
