"""The dock's entities table: one row per entity the costmap reads (name, geometry, threshold,
extra prompts), as the user edits it and as a project saves it.

Its own widget so that the mission section holds the mission's flow (interpret, fit, save) and
this file holds how a row is shown and read back."""

from __future__ import annotations

from collections.abc import Iterable

from qgis.PyQt.QtCore import pyqtSignal
from qgis.PyQt.QtWidgets import QComboBox, QHeaderView, QTableWidget, QTableWidgetItem

from overseec_core.schema import GEOMETRIES

ENTITY_COLUMNS = ("name", "geometry", "threshold", "extra prompts")
#: A row as a project saves it: the four columns' texts.
Cells = tuple[str, str, str, str]


class EntityTable(QTableWidget):
    """The table; ``edited`` fires on every change the user makes (a cell, a geometry, a row)."""

    edited = pyqtSignal()

    def __init__(self) -> None:
        super().__init__(0, len(ENTITY_COLUMNS))
        self.setHorizontalHeaderLabels(ENTITY_COLUMNS)
        self.horizontalHeader().setSectionResizeMode(QHeaderView.Stretch)
        self.setMinimumHeight(120)
        self.itemChanged.connect(lambda *_: self.edited.emit())

    def add_row(self, name: str, geometry: str, threshold: float | None, prompts: Iterable[str]) -> None:
        """Append an entity (``prompts``: its prompts; the name itself is implied)."""
        r = self.rowCount()
        self.insertRow(r)
        self.setItem(r, 0, QTableWidgetItem(name))
        combo = QComboBox()
        combo.addItems(list(GEOMETRIES))
        combo.setCurrentText(geometry)
        self.setCellWidget(r, 1, combo)
        self.setItem(r, 2, QTableWidgetItem("" if threshold is None else f"{threshold:g}"))
        self.setItem(r, 3, QTableWidgetItem(", ".join(p for p in prompts if p != name)))
        combo.currentTextChanged.connect(lambda *_: self.edited.emit())
        self.edited.emit()

    def remove_selected(self) -> None:
        """Remove the rows with a selected cell."""
        for r in sorted({i.row() for i in self.selectedIndexes()}, reverse=True):
            self.removeRow(r)
        self.edited.emit()

    def text(self, row: int, column: int) -> str:
        """One cell's text ("" for an empty cell); the geometry column reads its combo box."""
        if column == 1:
            return self.cellWidget(row, 1).currentText()
        item = self.item(row, column)
        return item.text() if item else ""

    def entity_rows(self) -> list[dict]:
        """The named rows as plain dicts (name, geometry, threshold or None, prompts); a
        threshold that is not a number is a ValueError naming the entity."""
        rows = []
        for r in range(self.rowCount()):
            name = self.text(r, 0).strip()
            if not name:
                continue
            thr_text = self.text(r, 2).strip()
            try:
                threshold = float(thr_text) if thr_text else None
            except ValueError:
                raise ValueError(f"entity {name!r}: threshold {thr_text!r} is not a number") from None
            extra = [p.strip() for p in self.text(r, 3).split(",") if p.strip()]
            rows.append(
                {
                    "name": name,
                    "geometry": self.text(r, 1),
                    "threshold": threshold,
                    "prompts": [name] + [p for p in extra if p != name] if extra else [],
                }
            )
        return rows

    def cells(self) -> tuple[Cells, ...]:
        """Every row's texts, as typed (what a project saves)."""
        return tuple(
            (self.text(r, 0), self.text(r, 1), self.text(r, 2), self.text(r, 3)) for r in range(self.rowCount())
        )

    def show_cells(self, rows: Iterable[Cells]) -> None:
        """Replace the table with saved rows, texts as they were typed."""
        self.setRowCount(0)
        for name, geometry, threshold, extra in rows:
            self.add_row(name, geometry, None, ())
            r = self.rowCount() - 1
            self.item(r, 2).setText(threshold)
            self.item(r, 3).setText(extra)
