"""Labelled data without xarray: named variables along named dimensions, with attributes.

:class:`LabelledData` holds what an :class:`xarray.Dataset` built from the same arguments would
hold (variables in the same order, coordinates, attributes, encodings) and reads the way the
project's readers of a results dataset read one (``ds["time"].values``, ``ds.coa.attrs``,
``"name" in ds``, ``ds.attrs``). :func:`rollerrig.output.write_dataset` writes either;
:meth:`LabelledData.to_xarray` gives the Dataset when one is asked for.

It exists for the one-run path: ``rollerrig simulate`` builds its results, writes them, draws
them and summarises them without importing xarray (and pandas and pyarrow under it, 0.4-0.5 s
of a fresh process on a quiet 2-core machine). It is no array library: no arithmetic, no
selection, no alignment; a reader that needs those asks for :meth:`~LabelledData.to_xarray`.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from typing import Any, NamedTuple

import numpy as np

__all__ = ["LabelledData", "Variable", "xarray_variable"]


def xarray_variable(dims, values, attrs=None, encoding=None):
    """An :class:`xarray.Variable` of ``values`` (imports xarray), built without xarray's
    probes of duck-array libraries where the values are a plain numpy array.

    xarray checks every array it is given against dask's array type, and finding that type
    imports ``dask.array`` whenever dask is installed (the studies extra): 0.25-0.75 s of a
    first ``Simulation.run()`` in a fresh process for a Dataset of numpy arrays
    (2026-12-01; issue 20). A plain array of numbers or strings needs none of that
    conversion, so it is handed over as it is (xarray's ``fastpath``); anything else (objects,
    dates and durations, which xarray converts; another array type) takes xarray's own path.

    Examples
    --------
    >>> v = xarray_variable(("time",), np.arange(3.0), {"units": "s"})
    >>> v.dims, v.attrs["units"], float(v.values[-1])
    (('time',), 's', 2.0)
    """
    import xarray as xr

    plain = type(values) is np.ndarray and values.dtype.kind not in "OMm"
    return xr.Variable(dims, values, attrs, encoding=encoding, fastpath=plain)


class Variable(NamedTuple):
    """One variable: its dimensions, values and attributes (and, read from a file, the
    encoding it was read with; empty otherwise)."""

    dims: tuple[str, ...]
    values: np.ndarray
    attrs: dict[str, Any]
    encoding: Mapping[str, Any] = {}  # read only here: copied where used

    @property
    def dtype(self) -> np.dtype:
        """The values' dtype."""
        return self.values.dtype

    @property
    def shape(self) -> tuple[int, ...]:
        """The values' shape."""
        return self.values.shape


def _variable(name: str, spec: Any) -> Variable:
    """A :class:`Variable` from xarray's constructor form ``(dims, values[, attrs])``."""
    if isinstance(spec, Variable):
        return spec
    if not isinstance(spec, tuple) or len(spec) not in (2, 3):
        raise TypeError(f"variable {name!r}: give (dims, values[, attrs]), got {type(spec)}")
    dims, values = spec[0], np.asarray(spec[1])
    dims = (dims,) if isinstance(dims, str) else tuple(dims)
    if values.ndim != len(dims):
        raise ValueError(f"variable {name!r}: dimensions {dims} for values of shape {values.shape}")
    return Variable(dims, values, dict(spec[2]) if len(spec) == 3 else {})


def _sizes(variables: Mapping[str, Variable]) -> dict[str, int]:
    """Dimension name -> length, in the order the variables first name them."""
    sizes: dict[str, int] = {}
    for name, var in variables.items():
        for dim, size in zip(var.dims, var.values.shape, strict=True):
            if sizes.setdefault(dim, size) != size:
                raise ValueError(
                    f"variable {name!r}: dimension {dim!r} has sizes {sizes[dim]} and {size}"
                )
    return sizes


class LabelledData(Mapping):
    """Variables along named dimensions with attributes: a Dataset's content, without xarray.

    Parameters
    ----------
    data_vars : mapping of name -> (dims, values[, attrs])
        The data variables, as :class:`xarray.Dataset` takes them.
    coords : mapping of name -> (dims, values[, attrs]), optional
        The coordinates (listed after the data variables, as xarray lists them).
    attrs : mapping, optional
        The dataset's attributes.

    Examples
    --------
    >>> import numpy as np
    >>> d = LabelledData({"f": ("time", np.ones(3), {"units": "N"})},
    ...                  coords={"time": ("time", np.arange(3.0), {"units": "s"})},
    ...                  attrs={"title": "x"})
    >>> list(d.variables), d.sizes, d.f.attrs["units"], "time" in d
    (['f', 'time'], {'time': 3}, 'N', True)
    """

    def __init__(
        self,
        data_vars: Mapping[str, Any],
        coords: Mapping[str, Any] | None = None,
        attrs: Mapping[str, Any] | None = None,
    ) -> None:
        coords = dict(coords or {})
        both = set(data_vars) & set(coords)
        if both:
            raise ValueError(f"names both data variable and coordinate: {sorted(both)}")
        self._variables = {str(n): _variable(str(n), v) for n, v in {**data_vars, **coords}.items()}
        self._coord_names = tuple(str(n) for n in coords)
        self.attrs: dict[str, Any] = dict(attrs or {})
        self._sizes = _sizes(self._variables)

    @classmethod
    def from_variables(
        cls,
        variables: Mapping[str, Variable],
        coord_names: Iterable[str],
        attrs: Mapping[str, Any] | None = None,
    ) -> LabelledData:
        """Variables in the order given (data variables and coordinates mixed, as in a file
        read back), those named in ``coord_names`` the coordinates."""
        coord_names = [str(n) for n in coord_names]
        out = cls({}, attrs=attrs)
        out._variables = {str(n): _variable(str(n), v) for n, v in variables.items()}
        out._coord_names = tuple(n for n in out._variables if n in coord_names)
        out._sizes = _sizes(out._variables)
        return out

    @classmethod
    def from_xarray(cls, ds) -> LabelledData:
        """The content of an :class:`xarray.Dataset` (values, attributes copied shallowly,
        encodings kept), in its order."""
        variables = {
            str(n): Variable(tuple(map(str, v.dims)), v.values, dict(v.attrs), dict(v.encoding))
            for n, v in ds.variables.items()
        }
        return cls.from_variables(variables, map(str, ds.coords), ds.attrs)

    def to_xarray(self):
        """The :class:`xarray.Dataset` of the same content (imports xarray)."""
        import xarray as xr

        def var(v: Variable):
            return xarray_variable(v.dims, v.values, dict(v.attrs), dict(v.encoding))

        ds = xr.Dataset(
            {n: var(v) for n, v in self.data_vars.items()},
            coords={n: var(self._variables[n]) for n in self._coord_names},
        )
        ds.attrs.update(self.attrs)
        return ds

    @property
    def variables(self) -> dict[str, Variable]:
        """Every variable, data variables first, then the coordinates (xarray's order)."""
        return dict(self._variables)

    @property
    def data_vars(self) -> dict[str, Variable]:
        """The data variables, in order."""
        return {n: v for n, v in self._variables.items() if n not in self._coord_names}

    @property
    def coords(self) -> dict[str, Variable]:
        """The coordinates, in order."""
        return {n: self._variables[n] for n in self._coord_names}

    @property
    def sizes(self) -> dict[str, int]:
        """Dimension name -> length."""
        return dict(self._sizes)

    dims = sizes

    def __getitem__(self, name: str) -> Variable:
        return self._variables[name]

    def __getattr__(self, name: str) -> Variable:
        variables = self.__dict__.get("_variables", {})
        if name in variables:
            return variables[name]
        raise AttributeError(f"{type(self).__name__} has no variable or attribute {name!r}")

    def __iter__(self) -> Iterator[str]:  # the data variables, as a Dataset iterates
        return iter(self.data_vars)

    def __len__(self) -> int:
        return len(self._variables) - len(self._coord_names)

    def __contains__(self, name: object) -> bool:
        return name in self._variables

    def __repr__(self) -> str:
        sizes = ", ".join(f"{k}: {v}" for k, v in self._sizes.items())
        return f"<LabelledData ({sizes}): {len(self)} data variables, coords {self._coord_names}>"
