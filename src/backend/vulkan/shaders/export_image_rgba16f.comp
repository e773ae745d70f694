#version 450
// Pass "export" into an R16G16B16A16_SFLOAT storage image; see export_image.glsl.
#define IMAGE_FORMAT rgba16f
#include "export_image.glsl"
