#!/usr/bin/env python3
"""Reads .vtu files with the VTK library and prints their contents as JSON on stdout.

Used by tests/io/test_vtk.cpp to check granule's VTK writer against the reference reader.
Usage: vtk_roundtrip.py FILE.vtu [FILE.vtu ...]
Output: {FILE: {"points": [[x, y, z], ...], "cell_types": [...], "cells": [[ids...], ...],
                "point_data": {name: {"type": T, "tuples": [[c0, c1, ...], ...]}},
                "cell_data": {...}, "field_data": {...}}, ...}
Floats are printed with repr (shortest round-trip form), so values compare exactly.
Exit status 2 (with a message on stderr) when the vtk module cannot be imported.
"""
import json
import sys


def arrays(data):
    out = {}
    for k in range(data.GetNumberOfArrays()):
        a = data.GetAbstractArray(k)
        n, c = a.GetNumberOfTuples(), a.GetNumberOfComponents()
        if a.GetDataType() in (10, 11):  # VTK_FLOAT, VTK_DOUBLE
            kind = "Float"
        else:
            kind = "Int" if a.GetDataTypeMin() < 0 else "UInt"
        out[a.GetName()] = {
            "type": "%s%d" % (kind, 8 * a.GetDataTypeSize()),
            "tuples": [[a.GetComponent(i, j) for j in range(c)] for i in range(n)],
        }
    return out


def main():
    if len(sys.argv) < 2:
        sys.stderr.write("usage: vtk_roundtrip.py FILE.vtu [FILE.vtu ...]\n")
        return 1
    try:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    except ImportError as e:
        sys.stderr.write("vtk_roundtrip.py: the python 'vtk' module is not available for %s (%s); "
                         "install python3-vtk9 (Debian) or 'pip install vtk'\n" % (sys.executable, e))
        return 2
    result = {}
    for name in sys.argv[1:]:
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(name)
        reader.Update()
        if reader.GetErrorCode() != 0:
            sys.stderr.write("vtk_roundtrip.py: VTK reported error code %d for %s\n" % (reader.GetErrorCode(), name))
            return 3
        grid = reader.GetOutput()
        pts = grid.GetPoints()
        cell_types, cells = [], []
        for i in range(grid.GetNumberOfCells()):
            c = grid.GetCell(i)  # an internal object, overwritten by the next call
            cell_types.append(c.GetCellType())
            cells.append([c.GetPointId(j) for j in range(c.GetNumberOfPoints())])
        result[name] = {
            "points": [list(pts.GetPoint(i)) for i in range(grid.GetNumberOfPoints())] if pts else [],
            "cell_types": cell_types,
            "cells": cells,
            "point_data": arrays(grid.GetPointData()),
            "cell_data": arrays(grid.GetCellData()),
            "field_data": arrays(grid.GetFieldData()),
        }
    json.dump(result, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
