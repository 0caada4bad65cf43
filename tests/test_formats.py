"""The export-format table (``overseec_core.formats``) is the one home of the formats: every row
has its writer, every writer its row, and the CLI and Processing offer exactly its names."""

from __future__ import annotations

from overseec_core import defaults, formats
from overseec_core.commands.spec import command_spec
from overseec_core.interop import COSTMAP_WRITERS, PATH_WRITERS


def test_every_format_has_a_writer_and_every_writer_a_format() -> None:
    assert tuple(COSTMAP_WRITERS) == formats.names("costmap") == defaults.COSTMAP_FORMATS
    assert tuple(PATH_WRITERS) == formats.names("path") == defaults.PATH_FORMATS
    assert {f.exports for f in formats.FORMATS} == {"costmap", "path"}
    assert all(f.suffix.startswith(".") and f.help and f.label for f in formats.FORMATS)


def test_the_cli_offers_the_table_and_says_what_each_format_is() -> None:
    for command, exports in (("export costmap", "costmap"), ("export path", "path")):
        assert command_spec(command).option("--to").choices == formats.names(exports)
    assert formats.describe("path").startswith("gpx: ")


def test_file_filters_name_every_suffix() -> None:
    assert formats.file_filter("path") == "GPX (*.gpx);;KML (*.kml);;CSV (*.csv)"
    assert all(f"*{formats.BY_NAME[n].suffix}" in formats.file_filter("costmap") for n in formats.names("costmap"))
