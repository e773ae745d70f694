#!/usr/bin/env python3
"""Checks that a binary runs on any x86-64: only code of the dispatched paths (functions in
the namespaces rtd::avx2 and rtd::avx512, src/core/simd.h) may use instructions beyond
baseline x86-64 (SSE2): AVX/AVX2/AVX-512 (VEX/EVEX encodings, ymm/zmm/mask registers), FMA,
F16C, BMI1/2, LZCNT, POPCNT, SSE3-SSE4.2. A function elsewhere that uses one would crash an
older CPU (for example an AVX2 copy of an inline function from a header, picked by the linker
for the whole library).

Usage: check_isa.py BINARY...   (exit status 1 and a list of offenders if any)
"""
import re
import subprocess
import sys

ALLOWED = ("rtd::avx2::", "rtd::avx512::")
# Mnemonics beyond SSE2 (besides every v-prefixed VEX/EVEX one).
BEYOND_SSE2 = {
    "popcnt", "lzcnt", "andn", "bextr", "blsi", "blsmsk", "blsr", "bzhi", "mulx", "pdep", "pext",
    "rorx", "sarx", "shlx", "shrx", "crc32", "movbe",  # (tzcnt is fine: GCC emits it as rep bsf, which older CPUs run as bsf)
    # SSE3 / SSSE3 / SSE4.1 / SSE4.2
    "addsubps", "addsubpd", "haddps", "haddpd", "hsubps", "hsubpd", "lddqu", "movddup", "movshdup", "movsldup",
    "pabsb", "pabsw", "pabsd", "palignr", "phaddw", "phaddd", "phaddsw", "phsubw", "phsubd", "phsubsw",
    "pmaddubsw", "pmulhrsw", "pshufb", "psignb", "psignw", "psignd",
    "blendps", "blendpd", "blendvps", "blendvpd", "dpps", "dppd", "extractps", "insertps", "movntdqa", "mpsadbw",
    "packusdw", "pblendvb", "pblendw", "pcmpeqq", "pextrb", "pextrd", "pextrq", "phminposuw", "pinsrb", "pinsrd",
    "pinsrq", "pmaxsb", "pmaxsd", "pmaxud", "pmaxuw", "pminsb", "pminsd", "pminud", "pminuw", "pmovsxbw",
    "pmovsxbd", "pmovsxbq", "pmovsxwd", "pmovsxwq", "pmovsxdq", "pmovzxbw", "pmovzxbd", "pmovzxbq", "pmovzxwd",
    "pmovzxwq", "pmovzxdq", "pmuldq", "pmulld", "ptest", "roundps", "roundpd", "roundss", "roundsd",
    "pcmpgtq", "pcmpestri", "pcmpestrm", "pcmpistri", "pcmpistrm",
}
# x86 mnemonics that start with v but are not vector extensions.
NOT_VECTOR = {"verr", "verw", "vmcall", "vmlaunch", "vmresume", "vmxoff", "vmxon", "vmread", "vmwrite", "vmptrld",
              "vmptrst", "vmclear", "vmfunc"}
FUNCTION = re.compile(r"^[0-9a-f]+ <(.*)>:$")
WIDE_REGISTER = re.compile(r"%(ymm|zmm)\d+|%k[0-7]\b")


def offenders(binary):
    out = subprocess.run(["objdump", "-d", "-C", "--no-show-raw-insn", binary], check=True, capture_output=True,
                         text=True).stdout
    bad = {}
    name = None
    for line in out.splitlines():
        m = FUNCTION.match(line)
        if m:
            name = m.group(1)
            continue
        if name is None or any(a in name for a in ALLOWED):
            continue
        parts = line.split("\t")
        if len(parts) < 2:
            continue
        insn = parts[-1].strip()
        if not insn:
            continue
        mnemonic = insn.split()[0]
        if mnemonic in ("rep", "repz", "repnz", "lock", "notrack", "bnd", "data16") and len(insn.split()) > 1:
            mnemonic = insn.split()[1]
        if (mnemonic.startswith("v") and mnemonic not in NOT_VECTOR) or mnemonic in BEYOND_SSE2 or \
                WIDE_REGISTER.search(insn):
            bad.setdefault(name, insn)
    return bad


def main():
    status = 0
    for binary in sys.argv[1:]:
        bad = offenders(binary)
        for name, insn in sorted(bad.items()):
            print(f"{binary}: {name}: {insn}")
        if bad:
            status = 1
            print(f"{binary}: {len(bad)} function(s) outside rtd::avx2/rtd::avx512 need more than baseline x86-64")
        else:
            print(f"{binary}: only rtd::avx2 and rtd::avx512 use instructions beyond baseline x86-64")
    return status


if __name__ == "__main__":
    sys.exit(main())
