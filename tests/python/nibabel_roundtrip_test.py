#!/usr/bin/python3
"""A phantom written by mesh4d-phantom as NIfTI, read by a foreign reader (nibabel), must have
the same labels, dims and spacing as mesh4d's own raw dump of it.

Usage: nibabel_roundtrip_test.py PATH/TO/mesh4d-phantom
"""
import os
import subprocess
import sys
import tempfile

import nibabel
import numpy

EXPECTED = {  # name: (dims, spacing), as documented in engine/domain/phantoms.h
    "hypersphere": ((32, 32, 32, 32), (1, 1, 1, 1)),
    "hypertorus": ((48, 48, 24, 24), (1, 1, 1, 1)),
    "ventricle": ((100, 100, 44, 15), (1.77, 1.77, 6, 1)),
    "blobs": ((48, 32, 32, 16), (1, 1, 1, 1)),
}


def check(phantom_bin, name, folder):
    nii = os.path.join(folder, name + ".nii.gz")
    raw = os.path.join(folder, name + ".raw")
    subprocess.run([phantom_bin, name, "--out", nii, "--raw", raw], check=True,
                   stdout=subprocess.DEVNULL)
    image = nibabel.load(nii)
    dims, spacing = EXPECTED[name]
    assert image.shape == dims, f"{name}: nibabel shape {image.shape}, expected {dims}"
    zooms = image.header.get_zooms()
    assert numpy.allclose(zooms, spacing, atol=1e-5), f"{name}: zooms {zooms}, expected {spacing}"
    data = numpy.asanyarray(image.dataobj)
    assert numpy.issubdtype(data.dtype, numpy.integer), f"{name}: dtype {data.dtype}"
    ours = numpy.fromfile(raw, dtype=numpy.uint8 if data.max() <= 255 else "<u2")
    ours = ours.reshape(dims, order="F")  # the raw dump is x fastest
    differing = int(numpy.count_nonzero(ours != data))
    assert differing == 0, f"{name}: {differing} voxels differ"
    labels = sorted(int(v) for v in numpy.unique(data))
    print(f"{name}: shape {image.shape}, zooms {tuple(float(z) for z in zooms)}, labels {labels}: identical")


def main():
    phantom_bin = sys.argv[1]
    with tempfile.TemporaryDirectory() as folder:
        for name in EXPECTED:
            check(phantom_bin, name, folder)
    print("4 passed, 0 failed")


if __name__ == "__main__":
    main()
