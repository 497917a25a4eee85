"""Readers and writers: gaitml-csv, the shared real data sets' native formats and phone-app exports."""

from gaitml.io._atomic import atomic_dir, atomic_path, write_csv, write_json, write_text
from gaitml.io._detect import FORMATS, detect_format, list_dataset, read_dataset, read_recording, read_segments
from gaitml.io.columns_csv import read_columns_csv
from gaitml.io.gaitmap import read_gaitmap_csv, read_gaitmap_table
from gaitml.io.gaitml_csv import read_gaitml_csv, read_gaitml_folder, write_gaitml_csv, write_manifest
from gaitml.io.ifsm import read_ifsm_xlsx
from gaitml.io.oxford import OXFORD_RATE_HZ, read_oxford_folder
from gaitml.io.phyphox import read_phyphox
from gaitml.io.sensor_logger import read_sensor_logger
from gaitml.io.tyrex import TyrexTruth, list_tyrex_folders, read_tyrex, read_tyrex_truth

__all__ = [
    "FORMATS",
    "OXFORD_RATE_HZ",
    "TyrexTruth",
    "atomic_dir",
    "atomic_path",
    "detect_format",
    "list_dataset",
    "list_tyrex_folders",
    "read_columns_csv",
    "read_dataset",
    "read_gaitmap_csv",
    "read_gaitmap_table",
    "read_gaitml_csv",
    "read_gaitml_folder",
    "read_ifsm_xlsx",
    "read_oxford_folder",
    "read_phyphox",
    "read_recording",
    "read_segments",
    "read_sensor_logger",
    "read_tyrex",
    "read_tyrex_truth",
    "write_csv",
    "write_gaitml_csv",
    "write_json",
    "write_manifest",
    "write_text",
]
