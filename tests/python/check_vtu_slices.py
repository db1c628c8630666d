#!/usr/bin/python3
"""Reads the .vtu time slices that `mesh4d-client export --vtu` wrote with VTK's own XML reader
and compares, per slice and label, the volume of the tetrahedra with the voxel volume of that
label in the image frame at the same time (read with nibabel).

usage: check_vtu_slices.py IMAGE.nii[.gz] VTU_DIR TOLERANCE [--frames F0,F1,...] [--time-scale S]

IMAGE is the image that was meshed (label 0 is background); TOLERANCE a relative error (0.02 is
2 %). The .pvd collection's time steps must be frame times: t = (frame) * time scale. Exits 1
when any (slice, label) is off by more than the tolerance, or when a slice lacks a label.
"""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import nibabel
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def slice_volumes(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfCells() == 0:
        return {}
    sizes = vtk.vtkCellSizeFilter()
    sizes.SetInputData(grid)
    sizes.ComputeVolumeOn()
    sizes.Update()
    out = sizes.GetOutput()
    volume = vtk_to_numpy(out.GetCellData().GetArray("Volume"))
    labels = vtk_to_numpy(out.GetCellData().GetArray("label"))
    types = {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())}
    if types != {vtk.VTK_TETRA}:
        raise SystemExit(f"{path}: cells other than tetrahedra: {types}")
    if (volume <= 0).any():
        raise SystemExit(f"{path}: {int((volume <= 0).sum())} tetrahedra without positive volume")
    return {int(l): float(volume[labels == l].sum()) for l in np.unique(labels)}


def main():
    args = sys.argv[1:]
    frames, time_scale = None, 1.0
    if "--frames" in args:
        i = args.index("--frames")
        frames = [int(f) for f in args[i + 1].split(",")]
        del args[i : i + 2]
    if "--time-scale" in args:
        i = args.index("--time-scale")
        time_scale = float(args[i + 1])
        del args[i : i + 2]
    image_path, vtu_dir, tolerance = args[0], Path(args[1]), float(args[2])
    image = nibabel.load(image_path)
    labels = np.asarray(image.dataobj)
    voxel = float(np.prod(image.header.get_zooms()[:3]))
    pvd = ET.parse(vtu_dir / "slices.pvd").getroot()
    failures = 0
    rows = 0
    print("| t | label | mesh volume | voxel volume | error |")
    print("|---|---|---|---|---|")
    for ds in pvd.iter("DataSet"):
        t = float(ds.get("timestep"))
        frame = round(t / time_scale)
        if abs(frame * time_scale - t) > 1e-9:
            raise SystemExit(f"slice at t = {t} is not a frame time")
        if frames is not None and frame not in frames:
            continue
        mesh = slice_volumes(vtu_dir / ds.get("file"))
        present = [int(l) for l in np.unique(labels[..., frame]) if l != 0]
        for label in present:
            expected = voxel * float((labels[..., frame] == label).sum())
            got = mesh.get(label, 0.0)
            error = (got - expected) / expected
            bad = abs(error) > tolerance
            failures += bad
            rows += 1
            print(f"| {t:g} | {label} | {got:.1f} | {expected:.1f} | {100 * error:+.2f} %"
                  f"{' FAIL' if bad else ''} |")
        for label in mesh:
            if label not in present:
                failures += 1
                print(f"| {t:g} | {label} | {mesh[label]:.1f} | 0 | label not in frame FAIL |")
    if rows == 0:
        raise SystemExit("no slice compared")
    print(f"{rows} (slice, label) pairs, {failures} beyond {100 * tolerance:g} %")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
