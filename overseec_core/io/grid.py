"""The image grid and its ground scale: CRS, transform, size, and pixel sizes in ground metres
(Web Mercator's scale factor, geodesic steps for geographic CRSs).
"""

from __future__ import annotations

import functools
import math
import threading
from dataclasses import dataclass

import numpy as np
from rasterio.crs import CRS
from rasterio.transform import Affine

from overseec_core.errors import InputError, RasterError

# --------------------------------------------------------------------------------------------
# Grid and georeferencing
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Grid:
    """The pixel grid outputs share with their input: CRS, transform and size."""

    crs: CRS
    transform: Affine
    width: int
    height: int

    @property
    def shape(self) -> tuple[int, int]:
        return (self.height, self.width)

    def same_as(self, other: Grid, tol: float = 1e-9) -> bool:
        """True when both grids are the same pixels in the same CRS."""
        return (
            self.shape == other.shape
            and self.crs == other.crs
            and self.transform.almost_equals(other.transform, precision=tol)
        )

    def pixel_size_m(self) -> tuple[float, float]:
        """Ground size (x, y) of one pixel in metres; see :func:`pixel_size_m`."""
        return pixel_size_m(self.crs, self.transform, self.width, self.height)

    def ground_scale(self) -> GroundScale:
        """How this grid's map units became ground metres; see :func:`ground_scale`."""
        return ground_scale(self.crs, self.transform, self.width, self.height)


#: A projected CRS keeps its nominal pixel size (transform step x linear unit) while the ground scale
#: measured at the image centre is within this relative tolerance of 1 on both axes (UTM's 0.9996 at
#: its central meridian, State Plane zones); beyond it the measured ground size is used.
NOMINAL_SCALE_TOLERANCE = 1e-3
#: Points per side of the lattice on which :func:`ground_scale` samples the scale across the image.
_SPAN_SAMPLES = 5
_MEASURE_LOCK = threading.Lock()


@dataclass(frozen=True)
class GroundScale:
    """How one grid's map units become ground metres: what :func:`pixel_size_m` returns, and why.

    ``pixel_size_m`` is the (x, y) size used everywhere; ``measured_m`` the geodesic ground size of
    one pixel step at the image centre (None where the CRS has no ellipsoid to measure on);
    ``nominal_m`` the transform step times the CRS's linear unit (None for geographic CRSs);
    ``factor`` = measured / nominal, the map's local scale at the centre (ground metres per map
    metre; 1 / k for a projection with point scale k). ``method`` says which was used: "nominal"
    (projected, scale within :data:`NOMINAL_SCALE_TOLERANCE` of 1), "scaled" (projected, measured
    size used), "geodesic" (geographic CRS) or "unmeasured" (no ellipsoid or outside the
    projection's domain: nominal size, scale unknown). ``span`` is (min, max) over the image of the
    true ground length of a one-pixel step (along x or y) divided by the length that
    ``pixel_size_m`` gives it: the relative error of lengths measured with one pixel size for the
    whole image (None where unmeasured).
    """

    pixel_size_m: tuple[float, float]
    method: str
    measured_m: tuple[float, float] | None = None
    nominal_m: tuple[float, float] | None = None
    factor: tuple[float, float] | None = None
    span: tuple[float, float] | None = None

    @property
    def max_error(self) -> float | None:
        """Largest relative length error anywhere in the image (0.0017 = 0.17 %), or None."""
        return None if self.span is None else max(abs(self.span[0] - 1.0), abs(self.span[1] - 1.0))

    def to_dict(self) -> dict:
        return {
            "pixel_size_m": list(self.pixel_size_m),
            "method": self.method,
            "measured_m": None if self.measured_m is None else list(self.measured_m),
            "nominal_m": None if self.nominal_m is None else list(self.nominal_m),
            "factor": None if self.factor is None else list(self.factor),
            "span": None if self.span is None else list(self.span),
            "max_error": self.max_error,
        }

    def describe(self) -> str:
        px, py = self.pixel_size_m
        tol = f"{100 * NOMINAL_SCALE_TOLERANCE:g} %"
        text = {
            "nominal": f"nominal (map units are ground metres within {tol})",
            "scaled": "scaled to ground metres at the image centre",
            "geodesic": "measured on the ellipsoid at the image centre",
            "unmeasured": "nominal (scale not measurable)",
        }[self.method]
        out = f"pixel {px:.6g} x {py:.6g} m, {text}"
        if self.factor is not None:
            out += f"; local scale {self.factor[0]:.6f} x {self.factor[1]:.6f} ground m per map m"
        if self.max_error is not None:
            out += f"; lengths within {100.0 * self.max_error:.2g} % across the image"
        return out


def pixel_size_m(crs: CRS, transform: Affine, width: int, height: int) -> tuple[float, float]:
    """Ground size of one pixel (x, y) in metres, for projected and geographic CRSs.

    Ground metres are geodesic distances on the CRS's ellipsoid (terrain height is ignored: 1000 m
    of elevation adds 0.016 %). One pixel step along x and along y is measured at the image centre
    (central differences, pixel ±0.5) after converting to the CRS's own geographic CRS:

    * geographic CRSs always use the measured size (pixels are not square on the ground: at 36 N a
      2.7e-6 degree pixel is about 0.24 m east-west and 0.30 m north-south);
    * projected CRSs keep their nominal size (transform step x linear unit) while the local scale
      is within :data:`NOMINAL_SCALE_TOLERANCE` (0.1 %) of 1 on both axes -- all of a UTM zone,
      State Plane and national survey grids, whose grid distances are the convention and whose
      stated resolution (0.5 m) users see in QGIS -- and use the measured size beyond it, e.g.
      Web Mercator, whose map metres are sec(latitude) ground metres (0.682 ground m per map m at
      47 N, 1.000 at the equator), or a UTM grid used far outside its zone;
    * CRSs without an ellipsoid (engineering/local) or a centre outside the projection's domain
      use the nominal size.

    One size serves the whole image: where the scale varies across it (Web Mercator: sec(lat)
    changes by about tan(lat) x the latitude span in radians: 0.17 % over 10 km of ground
    north-south at 47 N, so +-0.08 % at the edges), lengths away from the centre carry that error;
    :func:`ground_scale` reports it (``span``, ``max_error``) with the factor and the decision. Cached per
    (CRS, transform, size).
    """
    return ground_scale(crs, transform, width, height).pixel_size_m


def ground_scale(crs: CRS, transform: Affine, width: int, height: int) -> GroundScale:
    """The ground-metre decision behind :func:`pixel_size_m` with its factor and error (cached)."""
    if crs is None:
        raise RasterError("the raster has no CRS; pass --assume-crs EPSG:XXXX to say which it is")
    return _ground_scale(
        crs.to_wkt(),
        tuple(transform)[:6],
        int(width),
        int(height),
        bool(crs.is_geographic),
        bool(crs.is_projected),
        float(crs.linear_units_factor[1]) if crs.is_projected else 1.0,
    )


@functools.lru_cache(maxsize=32)
def _lonlat_measurer(wkt: str):
    """(transformer to the CRS's geographic CRS, degrees per its angle unit, Geod), or None."""
    import pyproj
    from pyproj import Geod, Transformer

    try:
        src = pyproj.CRS.from_wkt(wkt)
        geo = src.geodetic_crs
        if geo is None:
            return None
        if len(geo.axis_info) > 2:
            # CRS.to_2d is pyproj >= 3.6; on an older one this raises and the CRS keeps nominal sizes
            geo = geo.to_2d()  # type: ignore[attr-defined, unused-ignore]
        deg_per_unit = math.degrees(geo.axis_info[0].unit_conversion_factor)
        geod = geo.get_geod() or Geod(ellps="WGS84")
        return Transformer.from_crs(src, geo, always_xy=True), deg_per_unit, geod
    except Exception:  # pyproj raises CRSError/ProjError; an unmeasurable CRS keeps nominal sizes
        return None


def _ground_steps(measurer, transform: Affine, cols: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Geodesic length (m) of one pixel step along x and y centred on each (col, row); NaN where
    the points fall outside the projection's domain."""
    tr, deg, geod = measurer
    n = len(cols)
    c = np.concatenate([cols - 0.5, cols + 0.5, cols, cols])
    r = np.concatenate([rows, rows, rows - 0.5, rows + 0.5])
    x, y = transform * (c, r)
    with np.errstate(all="ignore"):
        lon, lat = (np.asarray(v, dtype=np.float64) * deg for v in tr.transform(x, y, errcheck=False))
    ok = np.isfinite(lon) & np.isfinite(lat) & (np.abs(lat) <= 90.0)
    lon, lat = np.where(ok, lon, 0.0), np.where(ok, lat, 0.0)
    dx = np.abs(geod.inv(lon[:n], lat[:n], lon[n : 2 * n], lat[n : 2 * n])[2])
    dy = np.abs(geod.inv(lon[2 * n : 3 * n], lat[2 * n : 3 * n], lon[3 * n :], lat[3 * n :])[2])
    dx = np.where(ok[:n] & ok[n : 2 * n], dx, np.nan)
    dy = np.where(ok[2 * n : 3 * n] & ok[3 * n :], dy, np.nan)
    return dx, dy


@functools.lru_cache(maxsize=256)
def _ground_scale(
    wkt: str, t: tuple, width: int, height: int, geographic: bool, projected: bool, unit_m: float
) -> GroundScale:
    transform = Affine(*t)
    nominal = (math.hypot(transform.a, transform.d) * unit_m, math.hypot(transform.b, transform.e) * unit_m)
    measurer = _lonlat_measurer(wkt) if (geographic or projected) else None
    if measurer is None:
        if geographic:
            raise RasterError("cannot measure pixel sizes in this geographic CRS (no ellipsoid)")
        return GroundScale(pixel_size_m=nominal, method="unmeasured", nominal_m=nominal if projected else None)
    k = _SPAN_SAMPLES
    cols, rows = np.meshgrid(np.linspace(0.0, width, k), np.linspace(0.0, height, k))
    with _MEASURE_LOCK:  # one pyproj transformer per CRS is shared; measure one grid at a time
        dx, dy = _ground_steps(measurer, transform, cols.ravel(), rows.ravel())
    centre = (k * k) // 2
    measured = (float(dx[centre]), float(dy[centre]))
    if not all(math.isfinite(v) and v > 0 for v in measured):
        if geographic:
            raise RasterError(
                f"cannot measure pixel sizes: the image centre is not a valid longitude/latitude (transform {tuple(t)})"
            )
        return GroundScale(pixel_size_m=nominal, method="unmeasured", nominal_m=nominal)
    if geographic:
        size, method, nom, factor = measured, "geodesic", None, None
    else:
        factor = (measured[0] / nominal[0], measured[1] / nominal[1])
        if all(abs(f - 1.0) <= NOMINAL_SCALE_TOLERANCE for f in factor):
            size, method = nominal, "nominal"
        else:
            size, method = measured, "scaled"
        nom = nominal
    ratios = np.concatenate([dx / size[0], dy / size[1]])
    ratios = ratios[np.isfinite(ratios)]
    span = (float(ratios.min()), float(ratios.max()))
    return GroundScale(
        pixel_size_m=(float(size[0]), float(size[1])),
        method=method,
        measured_m=measured,
        nominal_m=nom,
        factor=factor,
        span=span,
    )


def parse_crs(text: str) -> CRS:
    """A CRS from user text (EPSG:XXXX, WKT, PROJ string), or a one-line InputError."""
    try:
        return CRS.from_user_input(text)
    except Exception:  # rasterio raises CRSError, but GDAL can surface others
        raise InputError(f"not a CRS: {text!r} (use e.g. EPSG:32633)") from None


def crs_label(crs: CRS | None) -> str | None:
    """Short name for a CRS: 'EPSG:XXXX' when it has one, else its WKT."""
    if crs is None:
        return None
    epsg = crs.to_epsg()
    return f"EPSG:{epsg}" if epsg else crs.to_wkt()
