"""The planner kernel is portable C that pip builds from the sdist (issue 10).

QGIS users run Windows, macOS and Pythons other than Debian's, so the plugin ships no binary and
the kernel must compile anywhere: ISO C99/C11 with gcc and clang at -pedantic-errors, no GCC-only
names outside _portable.h's compiler guards, a plain-C fallback for the one builtin that agrees
with it, and a real sdist -> pip wheel -> import -> plan round trip.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import time
import zipfile
from pathlib import Path

import numpy
import pytest

REPO = Path(__file__).resolve().parents[2]
PLAN = REPO / "overseec_core" / "plan"
KERNEL = PLAN / "_kernel.c"
HEADER = PLAN / "_portable.h"
STRICT = ["-Wall", "-Wextra", "-Wvla", "-pedantic-errors", "-Werror"]  # -Wvla: MSVC has no VLAs
#: Spellings a compiler other than gcc/clang (MSVC) rejects, or that only MSVC accepts.
EXTENSIONS = re.compile(
    r"\b(__attribute__|__builtin_\w+|__extension__|__asm__|asm|__typeof__|typeof|__forceinline|__declspec|_BitScan\w+)\b"
)


def _includes() -> list[str]:
    # -isystem: NumPy's own headers are not -pedantic clean (object/function pointer casts);
    # the checks are about our source.
    return ["-isystem", sysconfig.get_paths()["include"], "-isystem", numpy.get_include(), "-I", str(PLAN)]


def _run(argv: list[str], cwd: Path | None = None, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    return subprocess.run(argv, capture_output=True, text=True, timeout=timeout, cwd=cwd)


def _compiler(name: str) -> str:
    path = shutil.which(name)
    if path is None:
        if name == "gcc":  # build-essential is part of `make setup`: its absence is a failure
            pytest.fail("gcc not found (make setup installs build-essential)")
        pytest.skip(f"{name} not installed")
    return path


@pytest.mark.parametrize("plain", [False, True], ids=["builtins", "plain-c"])
@pytest.mark.parametrize("std", ["c99", "c11"])
@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_kernel_is_strict_iso_c(cc: str, std: str, plain: bool) -> None:
    """Compiles as strict ISO C with each compiler, with and without the builtins branch."""
    argv = [_compiler(cc), f"-std={std}", *STRICT, "-fsyntax-only", *_includes(), str(KERNEL)]
    if plain:
        argv.insert(1, "-DOVERSEEC_PLAIN_C")
    done = _run(argv)
    assert done.returncode == 0, done.stderr


def _extensions_seen(source: Path) -> list[str]:
    """Compiler-specific names left in ``source`` (and the headers beside it) once the
    preprocessor has taken the plain-C branches; macros from system headers stay unexpanded."""
    argv = [_compiler("gcc"), "-E", "-fdirectives-only", "-std=c99", "-DOVERSEEC_PLAIN_C", *_includes(), str(source)]
    done = _run(argv)
    assert done.returncode == 0, done.stderr
    ours = {source.name, HEADER.name}
    found, current = [], ""
    for line in done.stdout.splitlines():
        marker = re.match(r'# \d+ "([^"]+)"', line)
        if marker:
            current = Path(marker.group(1)).name
        elif current in ours:
            found += [f"{current}: {m}" for m in EXTENSIONS.findall(line)]
    return found


def test_no_compiler_extensions_outside_the_guards() -> None:
    assert _extensions_seen(KERNEL) == []


def test_the_extension_check_catches_gcc_only_code(tmp_path: Path) -> None:
    """The check above is not vacuous: the kernel as it was before issue 10 fails it."""
    text = KERNEL.read_text(encoding="utf-8")
    old = tmp_path / "_kernel.c"
    old.write_text(
        text.replace("#pragma pack(push, 1)\ntypedef struct {", "typedef struct __attribute__((packed)) {").replace(
            "64 - clz64(key ^ last)", "64 - __builtin_clzll(key ^ last)"
        ),
        encoding="utf-8",
    )
    assert old.read_text(encoding="utf-8") != text
    assert sorted(_extensions_seen(old)) == ["_kernel.c: __attribute__", "_kernel.c: __builtin_clzll"]


CLZ_PROBE = r"""
#include <stdio.h>
#include "_portable.h"
int main(void) {
    uint64_t x = UINT64_C(0x9E3779B97F4A7C15);
    int k;
    for (k = 0; k < 64; k++) {
        uint64_t p = UINT64_C(1) << k;
        printf("%llu %d\n", (unsigned long long)p, clz64(p));
        printf("%llu %d\n", (unsigned long long)(p | (p - 1)), clz64(p | (p - 1)));
    }
    for (k = 0; k < 2000; k++) { /* xorshift64, shifted to vary the leading zeros */
        x ^= x << 13; x ^= x >> 7; x ^= x << 17;
        uint64_t v = (x >> (k % 64)) | 1;
        printf("%llu %d\n", (unsigned long long)v, clz64(v));
    }
    return 0;
}
"""


@pytest.mark.parametrize("plain", [False, True], ids=["builtin", "plain-c"])
def test_clz64_agrees_with_python(tmp_path: Path, plain: bool) -> None:
    """clz64 (the radix heap's bucket index) is right on both branches: builtin and fallback."""
    src = tmp_path / "probe.c"
    src.write_text(CLZ_PROBE, encoding="utf-8")
    exe = tmp_path / "probe"
    defines = ["-DOVERSEEC_PLAIN_C"] if plain else []
    done = _run([_compiler("gcc"), "-std=c99", *STRICT, "-O2", *defines, "-I", str(PLAN), str(src), "-o", str(exe)])
    assert done.returncode == 0, done.stderr
    out = _run([str(exe)])
    assert out.returncode == 0
    rows = [tuple(map(int, line.split())) for line in out.stdout.splitlines()]
    assert len(rows) == 2128
    for value, got in rows:
        assert got == 64 - value.bit_length(), (value, got)


MSVC_PROBE = r"""
#include "_portable.h"
OVERSEEC_FORCE_INLINE int twice(uint64_t x) { return 2 * clz64(x); }
int probe(uint64_t x) { return twice(x); }
#if !defined(OVERSEEC_CLZ_MSVC)
#error "the MSVC branch was not taken"
#endif
"""


@pytest.mark.parametrize("target", ["x86_64-pc-windows-msvc", "aarch64-pc-windows-msvc"])
def test_msvc_branch_compiles(tmp_path: Path, target: str) -> None:
    """_portable.h's MSVC spellings (__forceinline, _BitScanReverse64 from <intrin.h>) compile in
    clang's MSVC mode (_MSC_VER defined, Windows targets); freestanding, as no Windows SDK is here."""
    src = tmp_path / "probe.c"
    src.write_text(MSVC_PROBE, encoding="utf-8")
    ms = ["-ffreestanding", "-fms-extensions", "-fms-compatibility", "-fms-compatibility-version=19.30"]
    argv = [_compiler("clang"), f"--target={target}", *ms, "-std=c11", "-Wall", "-Wextra", "-Werror", "-O2"]
    done = _run([*argv, "-I", str(PLAN), "-c", str(src), "-o", str(tmp_path / "probe.obj")])
    assert done.returncode == 0, done.stderr


@pytest.mark.slow
def test_pip_builds_the_kernel_from_the_sdist(tmp_path: Path) -> None:
    """sdist -> ``pip wheel`` (compiles _kernel.c) -> the wheel's own kernel plans a grid."""
    sdist_dir, wheel_dir, unpacked = tmp_path / "sdist", tmp_path / "wheel", tmp_path / "site"
    done = _run([sys.executable, "setup.py", "-q", "sdist", "-d", str(sdist_dir)], cwd=REPO, timeout=300)
    assert done.returncode == 0, done.stderr
    (sdist,) = sdist_dir.glob("overseec-*.tar.gz")
    with tarfile.open(sdist) as tf:
        names = {Path(n).relative_to(Path(n).parts[0]).as_posix() for n in tf.getnames() if "/" in n}
    for needed in ("overseec_core/plan/_kernel.c", "overseec_core/plan/_portable.h", "overseec_core/plan/_kernel.pyi"):
        assert needed in names, needed
    assert not [n for n in names if n.endswith((".so", ".pyd", ".dylib"))]

    started = time.perf_counter()
    argv = [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--no-build-isolation", "-w", str(wheel_dir)]
    done = _run([*argv, str(sdist)], cwd=tmp_path, timeout=600)
    assert done.returncode == 0, done.stderr
    print(f"sdist -> wheel in {time.perf_counter() - started:.1f} s")
    (wheel,) = wheel_dir.glob("overseec-*.whl")
    with zipfile.ZipFile(wheel) as zf:
        built = [
            n for n in zf.namelist() if n.startswith("overseec_core/plan/_kernel.") and n.endswith((".so", ".pyd"))
        ]
        assert len(built) == 1, zf.namelist()
        zf.extractall(unpacked)

    # A fresh interpreter outside the checkout, with the wheel first on the path.
    env_script = REPO / "scripts" / "kernel_smoke.py"
    done = subprocess.run(
        [sys.executable, str(env_script)],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
        env={"PYTHONPATH": str(unpacked), "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)},
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert f"kernel {unpacked / built[0]}:" in done.stdout, done.stdout
