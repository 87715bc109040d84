"""Reading FretSim's HDF5 attributes, shared by the plot scripts.

Imported from the scripts' own folder (Python puts a script's folder first on
its path). Needs numpy (Debian's python3-numpy).
"""
import math

import numpy as np


def text_attribute(value):
    """An HDF5 string attribute as str, whatever h5py returns."""
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    if isinstance(value, np.ndarray) and value.size == 1:
        return text_attribute(value.item())
    return str(value)


def number_attribute(attrs, name):
    """A root attribute as a finite float (stored as a number or as text), or None."""
    if name not in attrs:
        return None
    value = attrs[name]
    try:
        if isinstance(value, (bytes, str)):
            value = float(text_attribute(value))
        else:
            value = float(np.asarray(value).reshape(-1)[0])
    except (TypeError, ValueError, IndexError):
        return None
    return value if math.isfinite(value) else None
