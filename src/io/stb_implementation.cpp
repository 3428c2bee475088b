// stb_image and stb_image_write's implementation, for builds with no libstb to link (a cross
// build to Windows: cmake/Par2dHostHeaders.cmake). Debian's libstb carries the same code.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
