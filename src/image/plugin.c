/* plugin.c — finding and opening the OpenImageIO plugin (libtocher_image.so, built
 * from encode.cpp) once per process, on the first image that needs it. */

/* Why a plugin: OpenImageIO and the libraries it pulls in cost every process that links
 * them load time and memory, whether it writes an image or not. Measured here (Debian 12,
 * OpenImageIO 2.4.7, 2 cores; a small program calling tc_img_load, then one 64x64 PNG
 * encode, reading VmRSS from /proc/self/status): loading takes 0.20-0.29 s warm (median
 * 0.25 s; 0.64 s with a cold page cache) and adds 122 MB of resident memory, 125 MB after
 * the first encode, against 0 s and 0.1 MB without. So commands and requests that produce
 * no image never load it, and raw float output is written without it (codec.c). Loading
 * happens once per process (pthread_once); the plugin is never unloaded, since
 * OpenImageIO keeps threads and static state.
 *
 * Where the plugin is looked for: $TOCHER_IMAGE_LIB if set (and then only there, so a
 * wrong setting is an error rather than a silent fallback), else libtocher_image.so next
 * to the running executable (the build tree), ../lib/libtocher_image.so relative to it
 * (an installed layout), and finally plain "libtocher_image.so" (dlopen's search path). */
#include <dlfcn.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image/plugin.h"

#define TC_IMG_PLUGIN_NAME "libtocher_image.so"

static pthread_once_t plugin_once = PTHREAD_ONCE_INIT;
static tc_img_plugin_fns plugin_fns;
static atomic_int plugin_ok;
static char plugin_error[4096]; /* why loading failed; written once under plugin_once */

/* Appends "; path: reason" to the report (dlerror() usually starts with the path
 * itself, which is not repeated). */
static void note_failure(char *report, size_t cap, const char *path, const char *reason) {
    size_t len = strlen(report), plen = strlen(path);
    if (!reason) reason = "unknown error";
    if (strncmp(reason, path, plen) == 0 && reason[plen] == ':') reason += plen + 1;
    while (*reason == ' ') reason++;
    if (len < cap) snprintf(report + len, cap - len, "%s%s: %s", len ? "; " : "", path, reason);
}

/* Opens one candidate and resolves its entry points; on failure appends the reason. */
static int try_plugin(const char *path, char *report, size_t cap) {
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        note_failure(report, cap, path, dlerror());
        return -1;
    }
    tc_img_plugin_abi_fn abi = (tc_img_plugin_abi_fn)dlsym(h, "tc_img_plugin_abi");
    tc_img_plugin_fns f = {
        (tc_img_stream_open_fn)dlsym(h, "tc_img_stream_open"),
        (tc_img_stream_rows_fn)dlsym(h, "tc_img_stream_rows"),
        (tc_img_stream_finish_fn)dlsym(h, "tc_img_stream_finish"),
        (tc_img_stream_free_fn)dlsym(h, "tc_img_stream_free"),
        (tc_img_decode_impl_fn)dlsym(h, "tc_img_decode_impl"),
    };
    int complete = abi && f.open && f.rows && f.finish && f.free && f.decode;
    if (!complete || abi() != TC_IMG_PLUGIN_ABI) {
        note_failure(report, cap, path, complete ? "built for another version of tocher (ABI mismatch)"
                                                 : "not a tocher image plugin (entry points missing)");
        dlclose(h);
        return -1;
    }
    plugin_fns = f;
    return 0;
}

/* The directory of the running executable, without the trailing '/'; 0 on success. */
static int exe_dir(char *dir, size_t cap) {
    ssize_t n = readlink("/proc/self/exe", dir, cap - 1);
    if (n <= 0 || (size_t)n >= cap - 1) return -1;
    dir[n] = '\0';
    char *slash = strrchr(dir, '/');
    if (!slash) return -1;
    *slash = '\0';
    return 0;
}

static int try_default_places(char *report, size_t cap) {
    char dir[4096], path[4096 + 64];
    if (exe_dir(dir, sizeof dir) == 0) {
        snprintf(path, sizeof path, "%s/" TC_IMG_PLUGIN_NAME, dir);
        if (try_plugin(path, report, cap) == 0) return 0;
        snprintf(path, sizeof path, "%s/../lib/" TC_IMG_PLUGIN_NAME, dir);
        if (try_plugin(path, report, cap) == 0) return 0;
    }
    return try_plugin(TC_IMG_PLUGIN_NAME, report, cap);
}

static void load_plugin(void) {
    char report[sizeof plugin_error - 128] = "";
    const char *env = getenv("TOCHER_IMAGE_LIB");
    int rc = env && *env ? try_plugin(env, report, sizeof report) : try_default_places(report, sizeof report);
    if (rc == 0) {
        atomic_store(&plugin_ok, 1);
        return;
    }
    snprintf(plugin_error, sizeof plugin_error, "cannot load the image plugin (OpenImageIO)%s: tried %s",
             env && *env ? " named by TOCHER_IMAGE_LIB" : "", report);
}

int tc_img_load(char *err, size_t errlen) {
    pthread_once(&plugin_once, load_plugin);
    if (atomic_load(&plugin_ok)) return 0;
    if (err && errlen) snprintf(err, errlen, "%s", plugin_error);
    return -1;
}

int tc_img_loaded(void) { return atomic_load(&plugin_ok); }

const tc_img_plugin_fns *tc__img_plugin(char *err, size_t errlen) {
    return tc_img_load(err, errlen) == 0 ? &plugin_fns : NULL;
}
