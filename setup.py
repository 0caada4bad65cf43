"""Build script for the native parts (setuptools reads the rest from pyproject.toml).

Native extensions are listed here because setuptools' pyproject.toml support has no stable
place for C extensions; each is compiled from source with the system compiler.
"""
from setuptools import setup

EXT_MODULES: list = []

setup(ext_modules=EXT_MODULES)
