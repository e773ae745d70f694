#version 450
// Pass "import" from an unsigned-integer VkImage (ids); see import_image.glsl.
#define IMAGE_TYPE utexture2D
#include "import_image.glsl"
