/* A C program on the installed package's C API: denoises two frames of a constant image. */
#include <rtd/capi.h>

#include <math.h>
#include <stdio.h>

int main(void) {
  float color[8 * 4 * 3], out[8 * 4 * 3];
  int i;
  RTDDevice device = rtdNewDevice(RTD_BACKEND_CPU);
  RTDDenoiser den;
  RTDImageView c = {color, 8, 4, RTD_FORMAT_FLOAT3, 0, 0}, o = {out, 8, 4, RTD_FORMAT_FLOAT3, 0, 0};
  const char* message = NULL;
  for (i = 0; i < 8 * 4 * 3; ++i) color[i] = 0.5f;
  if (rtdCommitDevice(device) != RTD_ERROR_NONE) return 1;
  den = rtdNewDenoiser(device, "accumulate");
  rtdSetDenoiserImage(den, "color", &c);
  rtdSetDenoiserImage(den, "output", &o);
  for (i = 0; i < 2; ++i)
    if (rtdDenoise(den) != RTD_ERROR_NONE) {
      rtdGetDeviceError(device, &message);
      printf("denoise failed: %s\n", message);
      return 1;
    }
  for (i = 0; i < 8 * 4 * 3; ++i)
    if (fabsf(out[i] - 0.5f) > 1e-6f) return 1;
  printf("C consumer ok: rtdenoise %s (headers %s), %d passes\n", rtdGetVersionString(), RTD_VERSION_STRING,
         rtdGetPassCount(den));
  rtdReleaseDenoiser(den);
  rtdReleaseDevice(device);
  return rtdGetVersion() == RTD_VERSION ? 0 : 1;
}
