"""Prints python-canopen's view of an EDS/DCF as JSON, for the Rust tests to compare with
`drivescript objects --json` field by field: one row per variable (index, subindex, name,
data type code, access type, limits, default). A file that is not UTF-8 is decoded as
Windows-1252 first (python-canopen reads UTF-8 only). Usage: python_canopen_view.py FILE
"""
import json
import os
import sys
import tempfile

import canopen
from canopen import objectdictionary as od_module


def rows(od):
    for obj in od.values():
        if isinstance(obj, od_module.ODVariable):
            yield obj, None
        else:
            for sub in obj.values():
                yield sub, obj


def main(path):
    raw = open(path, "rb").read()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        text = raw.decode("cp1252")
    suffix = os.path.splitext(path)[1]
    with tempfile.NamedTemporaryFile("w", suffix=suffix, delete=False, encoding="utf-8") as tmp:
        tmp.write(text)
    try:
        od = canopen.import_od(tmp.name)
    finally:
        os.unlink(tmp.name)
    out = []
    for var, parent in rows(od):
        default = var.default
        if isinstance(default, bytes):
            default = default.hex()
        out.append(
            {
                "index": var.index,
                "subindex": var.subindex,
                "name": var.name,
                "parent": parent.name if parent is not None else None,
                "data_type": var.data_type,
                "access": var.access_type,
                "min": var.min,
                "max": var.max,
                "default": default,
            }
        )
    json.dump({"canopen": canopen.__version__, "variables": out}, sys.stdout)


if __name__ == "__main__":
    main(sys.argv[1])
