"""Reading and writing demonstrations: CSV, .npz, HDF5, ROS 2 bags, LeRobot datasets.

Two levels:

* :func:`read_table` / :func:`write_table` move a header row and a numeric
  table between a CSV file and numpy, nothing more.
* :func:`read_csv` / :func:`write_csv`, :func:`read_npz` / :func:`write_npz`,
  :func:`read_hdf5`, :func:`read_bag` / :func:`write_bag`, :func:`read_lerobot`
  and :func:`read_demos` move whole :class:`~ndlfd.demonstration.Demonstration`
  objects; :func:`write_joint_trajectory` writes a ROS ``JointTrajectory`` as YAML.

The CSV dialect is deliberately small: one header row, numbers only below it,
separated by commas, semicolons, tabs or whitespace (the header row decides
which). Spaces around names and values are stripped; blank lines and lines
whose first non-space character is ``#`` are skipped anywhere (so a file may
carry comments). Quoting is not supported. Every problem is reported as a
:class:`~ndlfd.DataFileError` naming the file and the 1-based line number.

**Column mapping.** Every reader of demonstrations maps the file's columns (or
the arrays of an ``.npz`` / HDF5 file) to a time vector and physical groups the
same way: a time column (``t`` or ``time`` unless named), explicit
``groups={"position": ["pos_x", "pos_y"]}`` (a 2-D array maps all its columns),
and every other column by its name (:func:`group_of_column`; 2-D arrays named
``position``/``pos``, ``velocity``/``vel``, ``orientation``/``quat``,
``force``), or the names labs export (``current_pos_x``, ``joint_3``,
``torque_z``: :func:`lab_name`; a commanded set such as ``goal_pos_x`` beside
a measured one is left out with a warning). Names are matched
case-insensitively (an exact match wins); ``groups`` and ``drop`` take glob
patterns. Three orientation columns need their ``representation``
(``"rotvec"``, ``"euler-SEQ"``) unless named ``roll, pitch, yaw``. ``.npy``
files hold a bare array: their columns are named by ``columns=`` or a sidecar
``NAME.columns.txt``. The mapping used is returned as a :class:`ColumnMapping`
on request.

Every write goes to a temporary file beside the target and is renamed into place,
so a crash never leaves a partial file behind.

**Where each part lives.** ``_mapping`` (column names to groups,
:class:`ColumnMapping`, Euler angles), ``_names`` (the names labs export, a
mapping to paste), ``_rotations`` (orientation columns to quaternions),
``_csv`` (delimited text), ``_npz``, ``_npy``,
``_hdf5`` (with ``_aloha``: ALOHA / ACT episode files, two arms),
``_bag`` and ``_bagout`` (ROS 2 bags in and out, the ``ros`` extra;
``_tf`` their tf trees, ``_bag_frames`` their task frames), ``_frame_poses``
(a task frame's samples checked still and averaged),
``_lerobot`` (LeRobot dataset folders: one :class:`LeRobotEpisode` item per
episode) and ``_files`` (folders, glob patterns, :class:`DemoFile`,
:class:`DemoFiles` and the dispatch by suffix).

**Adding a reader** (a ROS 2 bag, a LeRobot dataset: ``_bag.py``,
``_lerobot.py``). A reader is a function ``reader(path, hints, **mapping)``
that returns a list of ``(Demonstration, ColumnMapping)`` pairs, one per
demonstration (episode) of the file. It gathers the file's named arrays and
hands each episode to :func:`~ndlfd.io._mapping.map_arrays`, which applies the
column mapping (``time_column``, ``groups``, ``quaternion_order``, ``drop``)
exactly as for CSV files and names the settings in errors through ``hints``
(``LIBRARY_HINTS`` or ``CLI_HINTS``). Register it in
:data:`~ndlfd.io._files.READERS` under its suffixes (and add them to
:data:`DEMO_SUFFIXES` if a folder should contribute such files); add a public
``read_<format>(path, **mapping)`` here. :func:`read_demos`, :class:`DemoFiles`,
``KeypointHMM.fit`` and the command line then read the format with no other
change. Options that only this reader takes (a bag's ``topic``) go into
:data:`~ndlfd.io._files.READER_OPTIONS`. An optional third-party library is
imported inside the reader, with a :class:`~ndlfd.MissingExtraError` that says
how to install it (see ``_hdf5``).
"""

from ._bag import BAG_TYPES, read_bag
from ._bagout import write_bag, write_joint_trajectory
from ._csv import (
    parse_table,
    read_csv,
    read_table,
    write_csv,
    write_table,
)
from ._files import (
    BAD_FILES,
    DEMO_SUFFIXES,
    DemoFile,
    DemoFiles,
    demo_files,
    read_demos,
    read_file,
    read_or_skip,
)
from ._hdf5 import read_hdf5
from ._lerobot import LeRobotEpisode, read_lerobot
from ._mapping import (
    ARRAY_NAMES,
    BAD_ROWS,
    CLI_HINTS,
    EULER_NAMES,
    MAPPING_DEFAULTS,
    NAMING_CONVENTION,
    TIME_NAMES,
    ColumnMapping,
    euler_columns,
    group_of_column,
)
from ._names import COMMANDED, MEASURED, lab_name
from ._npy import SIDECAR_SUFFIX, read_npy
from ._npz import read_npz, write_npz
from ._output import csv_columns, csv_header
from ._parquet import read_parquet, write_parquet

__all__ = [
    "ARRAY_NAMES",
    "BAD_FILES",
    "BAD_ROWS",
    "BAG_TYPES",
    "CLI_HINTS",
    "COMMANDED",
    "DEMO_SUFFIXES",
    "EULER_NAMES",
    "MAPPING_DEFAULTS",
    "MEASURED",
    "NAMING_CONVENTION",
    "SIDECAR_SUFFIX",
    "TIME_NAMES",
    "ColumnMapping",
    "DemoFile",
    "DemoFiles",
    "LeRobotEpisode",
    "csv_columns",
    "csv_header",
    "demo_files",
    "euler_columns",
    "group_of_column",
    "lab_name",
    "parse_table",
    "read_bag",
    "read_csv",
    "read_demos",
    "read_file",
    "read_hdf5",
    "read_lerobot",
    "read_npy",
    "read_npz",
    "read_or_skip",
    "read_parquet",
    "read_table",
    "write_bag",
    "write_csv",
    "write_joint_trajectory",
    "write_npz",
    "write_parquet",
    "write_table",
]
