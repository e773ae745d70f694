"""rtdenoise: real-time denoising of 1-spp path-traced frames (SVGF family, BMFR, accumulation).

Python bindings of the C++ library (docs/integration.md)::

    import rtdenoise
    den = rtdenoise.Device("cpu").create_denoiser("accumulate")
    out = den.denoise(color=c, albedo=a, normal=n, depth=z, motion=m)

Arrays are numpy arrays with rows from the top and channels last: H x W x 3 for colour, albedo,
normals; H x W for depth; H x W x 2 for motion (pixels to the previous position, y down). float32
and float16 arrays are read in place; others are converted. Buffer names are those of rtd::Buffer
(``buffer_names()``). Errors of the library raise ``rtdenoise.Error`` (a ValueError) with its message.
"""
from ._core import (
    Camera,
    Denoiser,
    Device,
    Error,
    Frame,
    SequenceReader,
    SequenceWriter,
    __version__,
    buffer_channels,
    buffer_names,
    convention_settings,
    eval,
    has_vulkan,
    list_devices,
    list_methods,
    read_exr,
    version_info,
    write_exr,
)

__all__ = [
    "Camera", "Denoiser", "Device", "Error", "Frame", "SequenceReader", "SequenceWriter", "__version__",
    "buffer_channels", "buffer_names", "convention_settings", "eval", "has_vulkan", "list_devices",
    "list_methods", "read_exr", "version_info", "write_exr",
]
