"""Build script for the native parts (setuptools reads the rest from pyproject.toml).

Native extensions are listed here because setuptools' pyproject.toml support has no stable
place for C extensions. The planner kernel is ISO C99 (compiler-specific spellings live in
_portable.h), so pip builds it from the sdist with whatever compiler the platform has: gcc or
clang (``unix``, ``mingw32``) or MSVC (``msvc``); each family gets its own flags below.
"""

import numpy
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

#: Optimisation and language flags by distutils compiler type (``build_ext.compiler.compiler_type``).
#: MSVC spells optimisation /O2 and has no -std (its C mode accepts the C99 the kernel uses).
COMPILE_ARGS: dict[str, list[str]] = {
    "unix": ["-O3", "-std=c99", "-Wall", "-Wno-unused-function"],
    "mingw32": ["-O3", "-std=c99", "-Wall", "-Wno-unused-function"],
    "msvc": ["/O2"],
}

EXT_MODULES: list = [
    # The planner's hot loop (Dijkstra on a bucket ring, A* on a radix heap); see _kernel.c.
    Extension(
        "overseec_core.plan._kernel",
        sources=["overseec_core/plan/_kernel.c"],
        depends=["overseec_core/plan/_portable.h"],
        include_dirs=[numpy.get_include(), "overseec_core/plan"],
        # Built against NumPy 2 (wheels), the module still imports under NumPy >= 1.23 (Debian 12
        # has 1.24); NumPy 1.x ignores the macro.
        define_macros=[("NPY_TARGET_VERSION", "NPY_1_23_API_VERSION")],
    ),
]


class BuildExt(build_ext):
    """build_ext with the flags of the compiler it actually found (known only at build time)."""

    def build_extensions(self) -> None:
        flags = COMPILE_ARGS.get(self.compiler.compiler_type, [])
        for ext in self.extensions:
            ext.extra_compile_args = [*flags, *(ext.extra_compile_args or [])]
        super().build_extensions()


setup(ext_modules=EXT_MODULES, cmdclass={"build_ext": BuildExt})
