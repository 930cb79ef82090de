"""Images as numpy arrays of shape (height, width, channels), top row first:

  PFM  linear float RGB, the pathtracer's -f X.pfm and --variance (little-endian,
       bottom row first on disk); read and written here (numpy only)
  PNG  8-bit, through PIL (Debian's python3-pil)
  EXR  float, through imageio's FreeImage plugin (python3-imageio, libfreeimage3)

read_image and write_image pick the format by the file's extension. Writes go to
a temporary file renamed into place, so a reader never sees half an image.
"""
import os

import numpy as np


def read_pfm(path):
    """A little-endian RGB or grey PFM as float32 (height, width, 3) or (height, width, 1)."""
    with open(path, "rb") as f:
        magic = f.readline().strip()
        if magic not in (b"PF", b"Pf"):
            raise ValueError(f"{path}: not a PFM (magic {magic!r})")
        width, height = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        if scale >= 0:
            raise ValueError(f"{path}: big-endian PFM (scale {scale}); the pathtracer writes little-endian")
        channels = 3 if magic == b"PF" else 1
        count = width * height * channels
        raw = f.read(4 * count)
    if len(raw) != 4 * count:
        raise ValueError(f"{path}: {len(raw)} of {4 * count} bytes of pixels")
    return np.frombuffer(raw, dtype="<f4").reshape(height, width, channels)[::-1]


def write_pfm(path, image):
    """Writes (height, width, 3) or (height, width, 1) floats, top row first, as a little-endian PFM."""
    image = np.asarray(image)
    if image.ndim == 2:
        image = image[:, :, None]
    height, width, channels = image.shape
    if channels not in (1, 3):
        raise ValueError(f"{path}: a PFM holds 1 or 3 channels, not {channels}")
    body = np.ascontiguousarray(image[::-1], dtype="<f4").tobytes()
    _write_atomically(path, f"{'PF' if channels == 3 else 'Pf'}\n{width} {height}\n-1.0\n".encode() + body)


def read_png(path):
    """An 8-bit PNG as uint8 (height, width, channels): RGB or RGBA as stored."""
    from PIL import Image

    with Image.open(path) as im:
        if im.mode not in ("RGB", "RGBA"):
            im = im.convert("RGB")
        return np.asarray(im)


def write_png(path, image):
    """Writes uint8 (height, width, 3 or 4), or floats in [0, 1] (clipped and rounded), as a PNG."""
    from PIL import Image

    image = np.asarray(image)
    if image.dtype != np.uint8:
        image = np.round(np.clip(image, 0.0, 1.0) * 255.0).astype(np.uint8)
    tmp = f"{path}.tmp{os.getpid()}.png"
    Image.fromarray(image).save(tmp)
    os.replace(tmp, path)


def _imageio():
    try:
        import imageio
    except ImportError as e:
        raise RuntimeError("EXR images need imageio's FreeImage plugin: apt install python3-imageio libfreeimage3") from e
    return imageio


def read_exr(path):
    """An OpenEXR image as float32 (height, width, channels)."""
    image = np.asarray(_imageio().imread(path, format="EXR-FI"), dtype=np.float32)
    return image[:, :, None] if image.ndim == 2 else image


def write_exr(path, image):
    """Writes floats (height, width, 3 or 4) as an OpenEXR image of 32-bit floats."""
    imageio = _imageio()
    tmp = f"{path}.tmp{os.getpid()}.exr"
    imageio.imwrite(tmp, np.asarray(image, dtype=np.float32), format="EXR-FI", flags=0x0001)  # EXR_FLOAT
    os.replace(tmp, path)


READERS = {".pfm": read_pfm, ".png": read_png, ".exr": read_exr}
WRITERS = {".pfm": write_pfm, ".png": write_png, ".exr": write_exr}


def read_image(path):
    """A PFM, PNG or EXR image by its extension."""
    return _by_extension(READERS, path)(path)


def write_image(path, image):
    """Writes a PFM, PNG or EXR image by its extension."""
    _by_extension(WRITERS, path)(path, image)


def _by_extension(table, path):
    ext = os.path.splitext(path)[1].lower()
    if ext not in table:
        raise ValueError(f"{path}: not a .pfm, .png or .exr image")
    return table[ext]


def _write_atomically(path, data):
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)
