#version 450
// Pass "import" from a float (or normalized) VkImage; see import_image.glsl.
#define IMAGE_TYPE texture2D
#include "import_image.glsl"
