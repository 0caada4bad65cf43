"""Plugin settings in QgsSettings (per user profile, never in the project file).

The environment, models, runs folder and LLM are edited on the plugin's page under Settings ›
Options (``options.py``); the dock edits the run parameters and the offline switch. Both load,
change their own fields and save (:meth:`PluginSettings.save_fields`), so neither overwrites
what the other changed.

Each refiner keeps its own checkpoint (``overseec/sam_models/<refiner>``: a SAM folder is no SAM 2
checkpoint); ``params.sam_model`` is the chosen refiner's, and choosing another refiner brings
its own back. The single ``overseec/sam_model`` of earlier versions is migrated on first load to
the refiner saved with it (``sam`` unless another was chosen) and removed.

The LLM API key is not a setting: it lives in QGIS's encrypted authentication database
(QgsAuthManager) as a "Basic" configuration whose password is the key; QgsSettings stores only
the configuration's id (``authcfg``), the way QGIS's own data sources do. A project file therefore
never holds the key, and neither does ``QGIS3.ini``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields, replace

from qgis.core import QgsApplication, QgsAuthMethodConfig, QgsSettings

from .params import REFINERS, Params

PREFIX = "overseec/"
#: Where each refiner's checkpoint is stored: PREFIX + SAM_MODELS + refiner name.
SAM_MODELS = "sam_models/"
#: The single refiner checkpoint setting of earlier versions (migrated, then removed).
OLD_SAM_MODEL = "sam_model"
AUTH_METHOD = "Basic"


@dataclass
class PluginSettings:
    """Everything the dock remembers between sessions (a mutable form model, not a value)."""

    #: Path to the `overseec` executable of the project's venv ("" = search, see worker.py).
    worker_path: str = ""
    #: The project's venv (used when QGIS's own Python lacks the core's dependencies).
    venv: str = ""
    #: What "Set up environment" installs: a checkout, sdist or wheel ("" = the checkout the
    #: plugin runs from, else the package overseec[models]).
    install_source: str = ""
    #: Parent directory for run directories ("" = overseec-runs beside the saved project, see dock.common.runs_root).
    runs_dir: str = ""
    offline: bool = True
    llm_endpoint: str = "http://localhost:11434/v1"
    llm_model: str = ""
    #: Id of the QgsAuthManager configuration that holds the API key ("" = no key).
    llm_authcfg: str = ""
    #: overseec_core version whose environment check passed ("" = check on next use).
    env_checked: str = ""
    #: Run parameters (stored flat: overseec/tile_size, overseec/refine, ...; ``sam_model`` is
    #: the chosen refiner's entry of ``sam_models``).
    params: Params = field(default_factory=Params)
    #: Each refiner's checkpoint ("" = that refiner's default), by refiner name.
    sam_models: dict[str, str] = field(default_factory=dict)

    @classmethod
    def load(cls) -> PluginSettings:
        s = QgsSettings()
        _migrate_sam_model(s)

        def read(f):
            return _coerce(s.value(PREFIX + f.name, f.default), f.default)

        own = {f.name: read(f) for f in fields(cls) if f.name not in ("params", "sam_models")}
        models = {
            r: _coerce(s.value(PREFIX + SAM_MODELS + r, ""), "")
            for r in REFINERS
            if s.contains(PREFIX + SAM_MODELS + r)
        }
        p = Params(**{f.name: read(f) for f in fields(Params) if f.name != "sam_model"})
        return cls(**own, params=replace(p, sam_model=models.get(p.refiner, "")), sam_models=models)

    def save(self) -> None:
        s = QgsSettings()
        values = {k: v for k, v in asdict(self).items() if k not in ("params", "sam_models")}
        values.update({k: v for k, v in asdict(self.params).items() if k != "sam_model"})
        self.sam_models = {**self.sam_models, self.params.refiner: self.params.sam_model}
        values.update({SAM_MODELS + r: m for r, m in self.sam_models.items()})
        for key, value in values.items():
            s.setValue(PREFIX + key, value)

    @classmethod
    def save_fields(cls, **changes) -> PluginSettings:
        """Load, change the named fields (own fields or Params fields), save; returns the result.

        The dock and the options page each save only what they edit through this."""
        current = cls.load()
        params = {k: v for k, v in changes.items() if k in {f.name for f in fields(Params)}}
        own = {k: v for k, v in changes.items() if k not in params}
        unknown = set(own) - {f.name for f in fields(cls)}
        if unknown:
            raise KeyError(f"no such setting: {', '.join(sorted(unknown))}")
        for key, value in own.items():
            setattr(current, key, value)
        if "refiner" in params and "sam_model" not in params:  # the new refiner's own checkpoint
            params["sam_model"] = current.sam_models.get(params["refiner"], "")
        if params:
            current.params = replace(current.params, **params)
        current.save()
        return current

    def api_key(self) -> str:
        """The LLM API key from the auth database, or "" when none is configured."""
        return load_api_key(self.llm_authcfg)


def _migrate_sam_model(s: QgsSettings) -> None:
    """The single ``sam_model`` of earlier versions becomes the checkpoint of the refiner saved
    beside it (``sam`` when none was), unless that refiner has one already; then it is removed."""
    if not s.contains(PREFIX + OLD_SAM_MODEL):
        return
    old = _coerce(s.value(PREFIX + OLD_SAM_MODEL, ""), "")
    refiner = _coerce(s.value(PREFIX + "refiner", Params().refiner), "")
    refiner = refiner if refiner in REFINERS else Params().refiner
    if old and not s.contains(PREFIX + SAM_MODELS + refiner):
        s.setValue(PREFIX + SAM_MODELS + refiner, old)
    s.remove(PREFIX + OLD_SAM_MODEL)


def _coerce(raw, default):
    """QSettings returns strings from ini files; give each field its declared type back."""
    if isinstance(default, bool):
        if isinstance(raw, str):
            return raw.strip().lower() in ("1", "true", "yes", "on")
        return bool(raw)
    if isinstance(default, int):
        try:
            return int(raw)
        except (TypeError, ValueError):
            return default
    if isinstance(default, float):
        try:
            return float(raw)
        except (TypeError, ValueError):
            return default
    return "" if raw is None else str(raw)


def load_api_key(authcfg: str) -> str:
    """Decrypt the key stored under ``authcfg`` ("" if there is none or it cannot be read)."""
    if not authcfg:
        return ""
    manager = QgsApplication.authManager()
    config = QgsAuthMethodConfig()
    if not manager.loadAuthenticationConfig(authcfg, config, True):
        return ""
    return config.config("password", "")


def store_api_key(key: str, name: str = "overseec LLM key", authcfg: str = "") -> str:
    """Store ``key`` encrypted in the auth database; returns the configuration id.

    Updates ``authcfg`` when given, else creates a new configuration. QGIS asks the user for the
    master password if it is not set yet. Raises RuntimeError if the database refuses.
    """
    manager = QgsApplication.authManager()
    config = QgsAuthMethodConfig(AUTH_METHOD)
    config.setName(name)
    config.setConfig("username", "")
    config.setConfig("password", key)
    if authcfg:
        config.setId(authcfg)
        ok = manager.updateAuthenticationConfig(config)
    else:
        ok = manager.storeAuthenticationConfig(config)
    if not ok or not config.id():
        raise RuntimeError("the QGIS authentication database did not store the key (is the master password set?)")
    return config.id()
