// The C interface of librtdenoise_oiio, the module through which librtdenoise reads image
// formats other than EXR (PFM, HDR, PNG, TIFF, ...) with OpenImageIO. librtdenoise loads it
// with dlopen() the first time such a file is read (src/io/image_file.cpp), so programs that
// never read one do not pay for loading OpenImageIO's ~250 shared libraries.
#pragma once

extern "C" {

/// What rtd_oiio_info() reports of a file's first subimage.
struct RtdOiioInfo {
  int width, height, channels;
  int integer;  ///< 1: stored as integers (PNG, 8/16-bit TIFF), read as values in [0, 1]
  int srgb;     ///< 1: OpenImageIO says its values are sRGB-encoded ("oiio:ColorSpace")
};

/// 0 on success; else writes a message of at most errorSize bytes to `error` and returns -1.
int rtd_oiio_info(const char* path, RtdOiioInfo* info, char* error, int errorSize);
/// Reads every channel of the first subimage as float, rows from the top, interleaved, into
/// `pixels` (width * height * channels floats); fails if the file no longer has the size and
/// channels of `expected` (what rtd_oiio_info() reported). 0 on success.
int rtd_oiio_read(const char* path, const RtdOiioInfo* expected, float* pixels, char* error, int errorSize);

typedef int (*RtdOiioInfoFn)(const char*, RtdOiioInfo*, char*, int);
typedef int (*RtdOiioReadFn)(const char*, const RtdOiioInfo*, float*, char*, int);
}
