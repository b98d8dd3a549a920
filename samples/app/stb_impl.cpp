// The one translation unit that holds stb_image_write's implementation (libstb-dev header).
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include "stb_image_write.h"
