"""The library inside other stacks, each with its optional extra.

- :mod:`.dask`: :func:`~.dask.associate` on Dask, for a picture larger than one machine, the
  same result as :func:`geofeas.associate` (``pip install 'geofeas[dask]'``);
  :mod:`._tiling` is its space-time grid;
- :mod:`.stonesoup`: Stone Soup measures backed by geofeasibility scores, the joint posterior of
  Stone Soup tracks (``PosteriorTrackAssociator``), tracks to and from report tables
  (``pip install 'geofeas[stonesoup]'``).

Nothing is imported here: each module needs its own extra, and raises an ``ImportError`` naming
it when that is missing.
"""
