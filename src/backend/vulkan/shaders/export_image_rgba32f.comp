#version 450
// Pass "export" into an R32G32B32A32_SFLOAT storage image; see export_image.glsl.
#define IMAGE_FORMAT rgba32f
#include "export_image.glsl"
