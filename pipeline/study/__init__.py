"""Studies: a TOML file names a grid of runs; Dask runs it; one CF netCDF file holds the results.

Where things are (each module one job):

- :mod:`~pipeline.study.studyfile`: the TOML study file, read and checked (:func:`load_study`,
  :func:`parse_study`, :func:`load_motions`);
- :mod:`~pipeline.study.spec`: what a checked study is (:class:`Study`, :class:`ColumnInfo`,
  :class:`RecordSpec`, :class:`Intensity`);
- :mod:`~pipeline.study.grid`: planning: tasks, scale factors, memory (:func:`plan`);
- :mod:`~pipeline.study.run`: one task on a worker (:func:`run_task`);
- :mod:`~pipeline.study.kernels`: the compiled kernels loaded, or compiled once, before the workers;
- :mod:`~pipeline.study.checkpoint`: finished tasks kept on disk, so that a killed run resumes;
- :mod:`~pipeline.study.cluster`: the Dask cluster (:class:`Cluster`), the only module that imports Dask;
- :mod:`~pipeline.study.results`: the result arrays and the Dataset they make (:func:`assemble`);
- :mod:`~pipeline.study.progress`: the progress bar;
- :mod:`~pipeline.study.orchestrate`: the whole run (:func:`run_study`).
"""

from pipeline.study.cluster import Cluster, scheduler_address
from pipeline.study.grid import block_size, check_memory, memory_estimate
from pipeline.study.orchestrate import RunReport, check_study_output, run_study, study_inputs
from pipeline.study.spec import ColumnInfo, Intensity, RecordSpec, Study
from pipeline.study.studyfile import load_motions, load_study, parse_study

__all__ = ["Study", "ColumnInfo", "RecordSpec", "Intensity", "load_study", "load_motions", "parse_study",
           "run_study", "RunReport", "Cluster", "scheduler_address", "check_study_output", "study_inputs",
           "check_memory", "memory_estimate", "block_size"]
