"""Run by ParaView's pvbatch (paraview_open_test.py): opens a dipc .xmf with both of ParaView's
XDMF readers ("XDMF Reader", XDMF 2, and "Xdmf3 Reader S") at the last time step and prints, per
reader, one JSON line: the number of time steps and, per block in order, its cells, its cell
and point arrays and the range of the cell field "body".

Usage: pvbatch --force-offscreen-rendering paraview_read.py FILE.xmf
"""
import json
import sys

from paraview import servermanager
from paraview.simple import XDMFReader, Xdmf3ReaderS


def leaves(data):
    """The data sets of a composite data set, depth first (collections and pieces opened)."""
    if data is None:
        return []
    if data.IsA("vtkMultiBlockDataSet"):
        return [leaf for i in range(data.GetNumberOfBlocks()) for leaf in leaves(data.GetBlock(i))]
    if data.IsA("vtkMultiPieceDataSet"):
        return [leaf for i in range(data.GetNumberOfPieces()) for leaf in leaves(data.GetPiece(i))]
    return [data]


def describe(reader):
    times = list(reader.TimestepValues)
    reader.UpdatePipeline(time=times[-1] if times else 0.0)
    blocks = []
    for block in leaves(servermanager.Fetch(reader)):
        cells, points = block.GetCellData(), block.GetPointData()
        body = cells.GetArray("body")
        blocks.append({"cells": block.GetNumberOfCells(),
                       "cell_arrays": sorted(cells.GetArrayName(j) for j in range(cells.GetNumberOfArrays())),
                       "point_arrays": sorted(points.GetArrayName(j) for j in range(points.GetNumberOfArrays())),
                       "body": list(body.GetRange()) if body is not None else None})
    return {"times": len(times), "blocks": blocks}


path = sys.argv[1]
for name, reader in (("xdmf2", XDMFReader(FileNames=[path])), ("xdmf3", Xdmf3ReaderS(FileName=[path]))):
    print("READ " + json.dumps({"reader": name, **describe(reader)}))
