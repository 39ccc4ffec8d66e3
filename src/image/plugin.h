/* plugin.h — the OpenImageIO plugin's entry points, loaded once on first use
 * (plugin.c), for the encoder and decoder fronts (codec.c). */
#ifndef TC_IMAGE_PLUGIN_H
#define TC_IMAGE_PLUGIN_H

#include "image/image.h"

/* Loads the plugin if need be and gives its entry points, or NULL with the
 * reason in err (the same reason every time: loading is tried once). */
const tc_img_plugin_fns *tc__img_plugin(char *err, size_t errlen);

#endif
