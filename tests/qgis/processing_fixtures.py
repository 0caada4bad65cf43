"""Fixtures of the Processing tests: private settings, the provider, an empty project.

A test module takes them all (``from .processing_fixtures import *``): ``private_settings`` is
autouse, so the module gets QgsSettings of its own. The provider's worker is this checkout's CLI
(``checkout_worker``: the venv's ``overseec`` runs the checkout it was installed from, which need
not be the one under test, e.g. a worktree beside it), unless the module sets
``CONFIGURED_WORKER = True`` (the worker the settings find, the venv's ``overseec``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from .conftest import REPO

__all__ = ["checkout_worker", "private_settings", "project", "provider"]


def settings_name(module: str) -> str:
    """An organisation name of its own for a test module's QgsSettings in this process: other
    test processes on the machine write the shared profile's overseec settings (a stub worker's
    venv, models) while these tests run, and the algorithms read them."""
    return f"overseec-{module.rsplit('.', 1)[-1].replace('_', '-')}-{os.getpid()}"


@pytest.fixture(scope="module", autouse=True)
def private_settings(qgis_app, request):
    """QgsSettings of this module's own, removed afterwards."""
    from qgis.core import QgsSettings
    from qgis.PyQt.QtCore import QCoreApplication

    before = QCoreApplication.organizationName()
    QCoreApplication.setOrganizationName(settings_name(request.module.__name__))
    yield
    Path(QgsSettings().fileName()).unlink(missing_ok=True)
    QCoreApplication.setOrganizationName(before)


@pytest.fixture(scope="module")
def checkout_worker(private_settings, tmp_path_factory) -> Path:
    """The worker pinned to this checkout's CLI, saved in the plugin's settings."""
    from overseec_qgis.settings import PluginSettings

    script = tmp_path_factory.mktemp("worker") / "overseec"
    script.write_text(
        f"#!/bin/sh\nPYTHONPATH={REPO} exec {sys.executable} -c "
        '"import sys; from overseec_core.console import main; sys.exit(main())" "$@"\n'
    )
    script.chmod(0o755)
    PluginSettings.save_fields(worker_path=str(script))
    return script


@pytest.fixture(scope="module")
def provider(qgis_processing, request):
    """The plugin's Processing provider (its worker this checkout's CLI unless the module sets
    ``CONFIGURED_WORKER``), unloaded after the module."""
    from overseec_qgis import classFactory

    if not getattr(request.module, "CONFIGURED_WORKER", False):
        request.getfixturevalue("checkout_worker")
    plugin = classFactory(None)
    plugin.initProcessing()
    yield plugin.provider
    plugin.unload()


@pytest.fixture
def project(qgis_new_project):
    """The current project, emptied before and after the test."""
    from qgis.core import QgsProject

    project = QgsProject.instance()
    project.removeAllMapLayers()
    project.layerTreeRoot().removeAllChildren()
    yield project
    project.removeAllMapLayers()
    project.layerTreeRoot().removeAllChildren()
