"""Input and output around the library: readers of outside formats and writers of its results.

- :mod:`.ais`: AIS recordings (Solent / MarineCadastre schemas) into clean trajectories, every
  removed row and corrected value reported with its reason (needs pandas);
- :mod:`.arrow`: pyarrow Tables and Parquet in and out of the association (the ``io`` extra).

Nothing is imported here: each module needs its own optional dependencies.
"""
