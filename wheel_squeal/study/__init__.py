"""Design and tolerance studies: many designs, each one task (mesh, modes, stability,
limit cycle, sound over an operating grid), run on a local process pool or a
dask.distributed cluster, gathered into an xarray Dataset.

:func:`load_spec` reads a study (``studies/*.toml``), :func:`run_study` runs it and
returns the Dataset; ``pipeline.py study`` is the command. xarray and dask are the
optional extra ``study``: the rest of the pipeline works without them.
"""

from .spec import Case, StudySpec, load_spec
from .task import CaseJob, run_case

__all__ = ["Case", "CaseJob", "StudySpec", "load_spec", "run_case"]
