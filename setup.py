"""Build script for the native parts (setuptools reads the rest from pyproject.toml).

Native extensions are listed here because setuptools' pyproject.toml support has no stable
place for C extensions; each is compiled from source with the system compiler.
"""

import numpy
from setuptools import Extension, setup

EXT_MODULES: list = [
    # The planner's hot loop (Dijkstra on a bucket ring, A* on a radix heap); see _kernel.c.
    Extension(
        "overseec_core.plan._kernel",
        sources=["overseec_core/plan/_kernel.c"],
        include_dirs=[numpy.get_include()],
        extra_compile_args=["-O3", "-std=c99", "-Wall", "-Wno-unused-function"],
    ),
]

setup(ext_modules=EXT_MODULES)
