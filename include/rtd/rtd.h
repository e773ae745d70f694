// rtdenoise — umbrella header.
#pragma once
#include "rtd/denoiser.h"
#include "rtd/error.h"
#include "rtd/frame.h"
#include "rtd/image.h"
#include "rtd/sequence.h"
#include "rtd/settings.h"
#include "rtd/stereo.h"
#include "rtd/version.h"
#include "rtd/methods/accumulate.h"
#include "rtd/methods/svgf.h"
#include "rtd/methods/bmfr.h"
