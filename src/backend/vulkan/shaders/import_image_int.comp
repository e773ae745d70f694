#version 450
// Pass "import" from a signed-integer VkImage (ids); see import_image.glsl.
#define IMAGE_TYPE itexture2D
#include "import_image.glsl"
