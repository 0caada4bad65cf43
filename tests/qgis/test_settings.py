"""Settings live in QgsSettings; the LLM API key only in QGIS's encrypted auth database."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from qgis.core import QgsApplication, QgsProject, QgsSettings

from overseec_qgis.options import PAGE_NAME
from overseec_qgis.settings import PluginSettings, load_api_key, store_api_key

pytestmark = pytest.mark.qgis

KEY = "sk-overseec-test-4b9f0c"


@pytest.fixture
def auth_ready():
    manager = QgsApplication.authManager()
    if manager.isDisabled():
        pytest.skip("QGIS authentication system disabled here")
    if not manager.masterPasswordIsSet():
        assert manager.setMasterPassword("overseec-test-master", True)
    return manager


def test_settings_round_trip_with_their_types(qgis_app) -> None:
    QgsSettings().remove("overseec")
    s = PluginSettings.load()
    assert s == PluginSettings()
    s.params = replace(s.params, tile_size=256, refine=False, tau_areal=0.7, device="cuda")
    s.offline, s.runs_dir = False, "/data/runs"
    s.save()
    again = PluginSettings.load()
    assert again == s
    assert isinstance(again.params.tile_size, int) and isinstance(again.params.refine, bool)
    assert isinstance(again.offline, bool) and isinstance(again.params.tau_areal, float)
    QgsSettings().remove("overseec")


def test_the_api_key_is_encrypted_and_never_in_settings_or_the_project(qgis_app, auth_ready, tmp_path) -> None:
    authcfg = store_api_key(KEY)
    assert authcfg and load_api_key(authcfg) == KEY
    # updating keeps the id
    assert store_api_key(KEY + "2", authcfg=authcfg) == authcfg and load_api_key(authcfg) == KEY + "2"
    store_api_key(KEY, authcfg=authcfg)
    s = PluginSettings.load()
    s.llm_authcfg = authcfg
    s.save()
    assert PluginSettings.load().api_key() == KEY
    settings_file = Path(QgsSettings().fileName())
    QgsSettings().sync()
    assert authcfg in settings_file.read_text() and KEY not in settings_file.read_text()
    project = tmp_path / "p.qgs"
    assert QgsProject.instance().write(str(project))
    assert KEY not in project.read_text()
    # the auth database holds it encrypted, not in clear text
    db = Path(QgsApplication.qgisAuthDatabaseFilePath())
    assert db.exists() and KEY.encode() not in db.read_bytes()
    assert load_api_key("") == "" and load_api_key("nosuch1") == ""
    QgsApplication.authManager().removeAuthenticationConfig(authcfg)
    QgsSettings().remove("overseec")


def test_the_options_page_keeps_only_the_auth_config_id(plugin, auth_ready) -> None:
    """The LLM moved to Settings › Options › overseec; the dock's offline switch decides."""
    authcfg = store_api_key(KEY)
    page = plugin.options_factory.createWidget(None)
    page.endpoint_edit.setText("http://127.0.0.1:9/v1")
    page.model_edit.setText("tiny")
    page.auth_select.setConfigId(authcfg)
    page.apply()
    dock = plugin.dock
    assert "http://127.0.0.1:9/v1" in dock.mission.llm_label.text() and "key stored" in dock.mission.llm_label.text()
    dock.mission.offline_check.setChecked(False)
    llm = dock.settings.llm_config()
    assert (llm.endpoint, llm.model, llm.api_key) == ("http://127.0.0.1:9/v1", "tiny", KEY)
    assert QgsSettings().value("overseec/llm_authcfg") == authcfg
    assert KEY not in str([QgsSettings().value(k) for k in QgsSettings().allKeys() if k.startswith("overseec")])
    dock.mission.offline_check.setChecked(True)
    assert dock.settings.llm_config().offline
    QgsApplication.authManager().removeAuthenticationConfig(authcfg)


def test_options_page_and_dock_save_only_their_own_fields(plugin, tmp_path) -> None:
    """Page and dock each save what they edit; neither overwrites the other's fields."""
    dock = plugin.dock
    page = plugin.options_factory.createWidget(None)
    assert page.objectName() == PAGE_NAME
    page.runs_widget.setFilePath(str(tmp_path / "runs"))
    page.clipseg_edit.setText(str(tmp_path / "clipseg"))
    page.device_combo.setCurrentText("cpu")
    page.venv_widget.setFilePath(str(tmp_path / "venv"))
    page.apply()
    dock.parameters.tile_spin.setValue(256)
    dock.parameters.refine_check.setChecked(False)
    dock.settings.save()  # the dock saves after the page: the page's fields survive
    s = PluginSettings.load()
    assert (s.runs_dir, s.venv, s.params.clipseg_model, s.params.device) == (
        str(tmp_path / "runs"),
        str(tmp_path / "venv"),
        str(tmp_path / "clipseg"),
        "cpu",
    )
    assert s.params.tile_size == 256 and s.params.refine is False
    assert (
        str(tmp_path / "clipseg") in dock.parameters.models_label.text()
        and str(tmp_path / "runs") in dock.parameters.models_label.text()
    )
    # a page opened later shows what is saved; applying it keeps the dock's fields
    again = plugin.options_factory.createWidget(None)
    assert again.clipseg_edit.text() == str(tmp_path / "clipseg") and again.device_combo.currentText() == "cpu"
    again.apply()
    assert PluginSettings.load().params.tile_size == 256
    with pytest.raises(KeyError, match="no such setting"):
        PluginSettings.save_fields(nonsense=1)
