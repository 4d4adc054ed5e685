/* stb_image's and stb_dxt's implementations, for the fuzz build only (see CMakeLists.txt). */
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

/* stb_dxt's block encoders too: the normal build takes both from Debian's libstb.so. */
#define STB_DXT_IMPLEMENTATION
#include <stb_dxt.h>
