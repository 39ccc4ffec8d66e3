/* plugin.h — the OpenImageIO plugin's entry points, loaded once on first use
 * (plugin.c), for the encoder and decoder fronts (codec.c). */
#ifndef TC_IMAGE_PLUGIN_H
#define TC_IMAGE_PLUGIN_H

#include "image/image.h"

/* Loads the plugin if need be and gives its entry points: 0, or -1 with the
 * reason in err (the same reason every time: loading is tried once). */
int tc__img_plugin(tc_img_encode_impl_fn *encode, tc_img_decode_impl_fn *decode, char *err, size_t errlen);

#endif
