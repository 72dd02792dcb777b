"""Helpers shared by the bench scripts' Python parts (no numpy: Debian's python3 alone).

PFM images as pmcr writes them (`-o NAME.pfm`), luminance and the perceptual threshold tvi as
host/metrics and host/image/tvi.cpp compute them, per-pixel variances over independent
renders, and the grids of mixture weights the ceiling benches render.
"""
import math
import struct


def read_pfm(path):
    """(width, height, flat RGB floats) of a colour PFM."""
    with open(path, "rb") as f:
        f.readline()
        w, h = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        n = w * h * 3
        data = struct.unpack(("<" if scale < 0 else ">") + "%df" % n, f.read(4 * n))
    return w, h, data


def write_pfm(path, w, h, data):
    """Writes flat RGB floats as a little-endian colour PFM (rows in the order read_pfm gives)."""
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(struct.pack("<%df" % (w * h * 3), *data))


def box_downsample(w, h, data, factor):
    """(w / factor, h / factor, RGB): each pixel the mean of a factor x factor block. With pmcr's
    box pixel filter this is exactly the reference of the coarser image, with factor^2 times
    the samples per pixel."""
    if w % factor or h % factor:
        raise ValueError(f"{w}x{h} is not divisible by {factor}")
    sw, sh = w // factor, h // factor
    out = [0.0] * (sw * sh * 3)
    inv = 1.0 / (factor * factor)
    for y in range(h):
        for x in range(w):
            i, o = 3 * (y * w + x), 3 * ((y // factor) * sw + x // factor)
            for c in range(3):
                out[o + c] += data[i + c] * inv
    return sw, sh, out


def luminances(data):
    """Rec. 709 luminance of each pixel of flat RGB floats."""
    return [0.2126 * data[i] + 0.7152 * data[i + 1] + 0.0722 * data[i + 2]
            for i in range(0, len(data), 3)]


def tvi(y, white=100.0):
    """Ferwerda et al. 1996 threshold versus intensity, in scene units (as host/image/tvi.cpp)."""
    la = max(y * white, 1e-6)
    l = math.log10(la)
    p = -0.72 if l <= -2.6 else (l - 1.255 if l >= 1.9 else (0.249 * l + 0.65) ** 2.7 - 0.72)
    s = -2.86 if l <= -3.94 else (l - 0.395 if l >= -1.44 else (0.405 * l + 1.6) ** 2.18 - 2.86)
    return min(10 ** p, 10 ** s) / white


def pixel_stats(paths):
    """(width, height, means, variances): each pixel's luminance mean and unbiased sample
    variance over independent renders."""
    images = [read_pfm(p) for p in paths]
    w, h, _ = images[0]
    ys = [luminances(data) for _, _, data in images]
    n = len(ys)
    means, variances = [], []
    for p in range(w * h):
        v = [y[p] for y in ys]
        m = sum(v) / n
        means.append(m)
        variances.append(sum((x - m) ** 2 for x in v) / (n - 1))
    return w, h, means, variances


def blur(values, w, h, r):
    """Mean over the (2r+1)^2 neighbourhood of each pixel, clipped at the image's edges."""
    if r == 0:
        return list(values)
    out = []
    for y in range(h):
        for x in range(w):
            ys, xs = range(max(0, y - r), min(h, y + r + 1)), range(max(0, x - r), min(w, x + r + 1))
            out.append(sum(values[j * w + i] for j in ys for i in xs) / (len(ys) * len(xs)))
    return out


def simplex_grid(components, step):
    """Weight vectors of `components` non-negative weights summing to one, in steps of `step`,
    written as pmcr's options take them ("0.25/0.75/0")."""
    units = round(1 / step)

    def tuples(n, total):
        if n == 1:
            yield (total,)
            return
        for first in range(total + 1):
            for rest in tuples(n - 1, total - first):
                yield (first,) + rest

    return ["/".join(f"{x / units:g}" for x in t) for t in tuples(components, units)]
