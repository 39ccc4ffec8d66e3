/* main.c — the tocher command-line tool: the JSON API of the daemon, on files.
 * `tocher ordinates MESH.json`, `tocher eval MESH.json [POINTS.json]`; "-" is stdin. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/leakcheck.h"
#include "image/format.h"
#include "io/api.h"
#include "io/options.h"
#include "io/request_write.h"
#include "scenes/meshing.h"
#include "tocher.h"

enum { EXIT_USAGE = 2, EXIT_INPUT = 3, EXIT_IO = 4, EXIT_INTERNAL = 5 };

static const char usage[] =
    "usage: tocher <command> [arguments]\n"
    "\n"
    "commands:\n"
    "  ordinates MESH.json [-o OUT]              Bezier ordinates of the reconstruction\n"
    "  eval MESH.json [POINTS.json] [-o OUT]     values (and gradients) at points\n"
    "  render MESH.json [-o OUT]                 an image tile of the \"viewport\" in MESH.json\n"
    "  compare MESH.json [-o OUT]                each method's error against \"reference\" samples\n"
    "  scene NAME [--mesh disc|uniform|adaptive|dm] [--density N] [--gradients]\n"
    "        [--no-midpoints] [--threshold T] [--depth D] [--quads] [--no-c0]\n"
    "        [--digits D] [--rotate DEG] [--window X0,Y0,X1,Y1] [-o OUT]\n"
    "                                            a reference scene meshed and sampled, as MESH.json\n"
    "                                            (--quads: one quad per cell, method hermite;\n"
    "                                            dm: fans as discontinuity meshers make them;\n"
    "                                            --no-c0: kinks left unflagged; --digits: values\n"
    "                                            rounded as printed; --rotate: dm scene turned;\n"
    "                                            --window: mesh only that rectangle of the plane)\n"
    "  scene --list                              the reference scenes\n"
    "  version                                   print the version\n"
    "  help                                      this text\n"
    "\n"
    "MESH.json is a request as POSTed to the daemon (see api/openapi.yaml):\n"
    "vertices, triangles, values, optional gradients, midpoints, discontinuities,\n"
    "and the options listed below. For eval, \"points\" and\n"
    "\"with_gradients\" come from POINTS.json, or from MESH.json if it has them.\n";

/* Then the render paragraph (render_help), then: */
static const char usage_tail[] =
    "Output goes to standard output (or OUT); errors go to standard error,\n"
    "naming the JSON path at fault.\n"
    "\n"
    "options:\n"
    "  -o OUT          write the output to OUT\n"
    "  --threads N     render with N threads (default: all CPUs)\n"
    "  --timings       add the \"timings\" object the daemon adds to JSON responses\n"
    "\n"
    "exit status: 0 ok, 2 usage, 3 invalid input, 4 file error, 5 internal error\n"
    "\n"
    "request options (the default first; in brackets the methods that read it):\n";

/* Appends word to the paragraph in buf, starting a new line where the current
 * one would pass `width` columns; *col is the current line's length. */
static void wrap_word(char *buf, size_t cap, size_t *col, const char *word, size_t width) {
    size_t len = strlen(buf), n = strlen(word);
    if (len + n + 2 >= cap) return;
    if (*col && *col + 1 + n > width) buf[len++] = '\n', *col = 0;
    else if (*col) buf[len++] = ' ', (*col)++;
    memcpy(buf + len, word, n + 1);
    *col += n;
}

/* The render paragraph of the usage, the extensions from the format table. */
static void render_help(char *buf, size_t cap) {
    char text[512], exts[128] = "";
    size_t n = 0, col = 0;
    for (int f = 0; f < TC_IMG_NFORMATS; f++)
        for (int i = 0; i < 3 && tc_img_traits_of((tc_img_format)f)->ext[i]; i++)
            n += (size_t)snprintf(exts + n, n < sizeof exts ? sizeof exts - n : 0, "%s%s", n ? " " : "",
                                  tc_img_traits_of((tc_img_format)f)->ext[i]);
    snprintf(text, sizeof text,
             "For render, the format is MESH.json's \"format\", else OUT's extension (%s), else %s. A file name of - "
             "reads standard input.",
             exts, tc_img_format_name(TC_IMG_DEFAULT));
    buf[0] = '\0';
    for (char *save = NULL, *w = strtok_r(text, " ", &save); w; w = strtok_r(NULL, " ", &save))
        wrap_word(buf, cap, &col, w, 78);
    if (strlen(buf) + 1 < cap) strcat(buf, "\n");
}

/* The usage, then every request option from the options table (io/options.c)
 * with what it accepts and which methods read it (the method table). */
static void print_usage(FILE *f) {
    tc_options def_opt;
    tc_mesh_desc def_desc;
    char render[600];
    tc_opt_defaults(&def_opt, &def_desc);
    render_help(render, sizeof render);
    fputs(usage, f);
    fputs(render, f);
    fputs(usage_tail, f);
    for (int i = 0; i < tc_opt_count(); i++) {
        const tc_opt *row = tc_opt_at(i);
        char accepts[256];
        tc_opt_accepts(row, accepts, sizeof accepts);
        fprintf(f, "  %-16s %s", row->name, accepts);
        if (row->kind == TC_OPT_NUMBER)
            fprintf(f, ", default %g", tc_opt_get_number(row, tc_opt_object(row, &def_opt, &def_desc)));
        if (row->target == TC_OPT_MESH) fputs(" [the mesh: every method]", f);
        for (int m = 0, n = 0; row->target == TC_OPT_RECON && row->reads && m < tc_method_count(); m++)
            if (tc_opt_read_by(row, (tc_method)m)) fprintf(f, "%s%s", n++ ? ", " : " [", tc_method_name((tc_method)m));
        fputs(row->target == TC_OPT_RECON && row->reads ? "]\n" : "\n", f);
    }
}

typedef struct {
    const char *cmd, *files[2], *out;
    int nfiles, threads, timings;
} args;

/* Reads a whole file ("-" = stdin) into a malloc'd buffer. */
static char *read_all(const char *path, size_t *len) {
    FILE *f = strcmp(path, "-") ? fopen(path, "rb") : stdin;
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n, f);
        if (n < cap) break;
        char *grown = realloc(buf, cap *= 2);
        if (!grown) free(buf);
        buf = grown;
    }
    int failed = ferror(f);
    if (f != stdin) fclose(f);
    if (failed) {
        free(buf);
        return NULL;
    }
    *len = n;
    return buf;
}

static void report(const args *a, const tc_api_result *res) {
    for (int i = 0; i < res->diags.count; i++) {
        const tc_diag *d = &res->diags.items[i];
        const char *file = i >= res->second_doc && a->nfiles > 1 ? a->files[1] : a->files[0];
        fprintf(stderr, "tocher: %s: %s%s%s%s\n", file, d->severity == TC_SEV_ERROR ? "error: " : "warning: ",
                d->path, *d->path ? ": " : "", d->message);
    }
    int shown = res->diags.count, all = res->diags.errors + res->diags.warnings;
    if (all > shown) fprintf(stderr, "tocher: ... and %d more findings\n", all - shown);
}

static int write_out(const char *path, const tc_strbuf *b) {
    FILE *f = path ? fopen(path, "wb") : stdout;
    if (!f) {
        fprintf(stderr, "tocher: %s: %s\n", path, strerror(errno));
        return EXIT_IO;
    }
    int ok = fwrite(b->buf, 1, b->len, f) == b->len;
    ok &= (f == stdout ? fflush(f) : fclose(f)) == 0;
    if (!ok) fprintf(stderr, "tocher: %s: write failed\n", path ? path : "stdout");
    return ok ? 0 : EXIT_IO;
}

static int parse_args(int argc, char **argv, args *a) {
    memset(a, 0, sizeof *a);
    a->cmd = argc > 1 ? argv[1] : "help";
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "-o") && i + 1 < argc) a->out = argv[++i];
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc && atoi(argv[i + 1]) > 0) a->threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--timings")) a->timings = 1;
        else if (a->nfiles < 2 && (argv[i][0] != '-' || !strcmp(argv[i], "-"))) a->files[a->nfiles++] = argv[i];
        else return -1;
    }
    return 0;
}

static int dispatch(const args *a, const char *body, size_t len, const char *pts, size_t plen, tc_strbuf *out,
                    tc_api_result *res) {
    if (!strcmp(a->cmd, "ordinates")) return tc_api_ordinates(body, len, NULL, out, res);
    if (!strcmp(a->cmd, "eval")) return tc_api_evaluate(body, len, pts, plen, NULL, out, res);
    if (!strcmp(a->cmd, "compare")) return tc_api_compare(body, len, NULL, out, res);
    long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
    tc_api_limits lim = {.render_threads = a->threads ? a->threads : (ncpu > 0 ? (int)ncpu : 1)};
    return tc_api_render_as(body, len, tc_img_format_of_path(a->out), &lim, out, res); /* the extension's format */
}

static int run(const args *a) {
    size_t len = 0, plen = 0;
    char *body = read_all(a->files[0], &len), *pts = NULL;
    if (!body) {
        fprintf(stderr, "tocher: %s: %s\n", a->files[0], strerror(errno));
        return EXIT_IO;
    }
    if (a->nfiles > 1 && !(pts = read_all(a->files[1], &plen))) {
        fprintf(stderr, "tocher: %s: %s\n", a->files[1], strerror(errno));
        free(body);
        return EXIT_IO;
    }
    tc_api_result res;
    tc_strbuf out;
    tc_api_result_init(&res);
    tc_strbuf_init(&out);
    int status = dispatch(a, body, len, pts, plen, &out, &res);
    if (status == 200 && a->timings) tc_api_add_timings(&out, &res);
    report(a, &res);
    int rc = status == 200 ? write_out(a->out, &out) : status == 500 ? EXIT_INTERNAL : EXIT_INPUT;
    tc_strbuf_free(&out);
    tc_api_result_free(&res);
    free(body), free(pts);
    return rc;
}

/* ---- tocher scene: the built-in front-end (src/scenes) ---- */

/* "tocher: unknown WHAT 'BAD' (known: a, b, c)" (or "no WHAT given") on standard error. */
static void list_known(const char *what, const char *bad, const char *(*name_of)(int), int n) {
    if (bad) fprintf(stderr, "tocher: unknown %s '%s' (known:", what, bad);
    else fprintf(stderr, "tocher: no %s given (known:", what);
    for (int i = 0; i < n; i++) fprintf(stderr, "%s %s", i ? "," : "", name_of(i));
    fputs(")\n", stderr);
}
static const char *scene_name_of(int i) { return tc_scene_name((tc_scene_id)i); }
static const char *kind_name_of(int i) { return tc_scene_mesh_kind_name((tc_scene_mesh_kind)i); }

/* A whole-string integer in [lo, hi]; 0, or -1 with a message. */
static int int_arg(const char *flag, const char *s, long lo, long hi, int *out) {
    char *end;
    errno = 0;
    long x = strtol(s, &end, 10);
    if (end == s || *end || errno || x < lo || x > hi) {
        fprintf(stderr, "tocher: %s %s: expected an integer from %ld to %ld\n", flag, s, lo, hi);
        return -1;
    }
    *out = (int)x;
    return 0;
}

/* A whole-string number >= 0; 0, or -1 with a message. */
static int threshold_arg(const char *s, double *out) {
    char *end;
    errno = 0;
    *out = strtod(s, &end);
    if (end == s || *end || errno || !(*out >= 0)) {
        fprintf(stderr, "tocher: --threshold %s: expected a number >= 0\n", s);
        return -1;
    }
    return 0;
}

/* A whole-string finite number; 0, or -1 with a message. */
static int number_arg(const char *flag, const char *s, double *out) {
    char *end;
    errno = 0;
    *out = strtod(s, &end);
    if (end == s || *end || errno || !isfinite(*out)) {
        fprintf(stderr, "tocher: %s %s: expected a number\n", flag, s);
        return -1;
    }
    return 0;
}

/* Applies the option at argv[*i] (moving *i past its value, if it takes one). */
/* "X0,Y0,X1,Y1" with X0 < X1 and Y0 < Y1; 0, or -1 with a message. */
static int window_arg(const char *s, double w[4]) {
    int n = -1;
    if (sscanf(s, "%lf,%lf,%lf,%lf%n", &w[0], &w[1], &w[2], &w[3], &n) == 4 && n == (int)strlen(s) &&
        isfinite(w[0] + w[1] + w[2] + w[3]) && w[0] < w[2] && w[1] < w[3])
        return 0;
    fprintf(stderr, "tocher: --window %s: expected X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1\n", s);
    return -1;
}

typedef struct {
    const char *name, *out;
    int windowed;
    double window[4];
} scene_args;

static int scene_option(int argc, char **argv, int *i, tc_scene_mesh_opts *o, scene_args *sa) {
    static const char *const valued[] = {"--mesh", "--density", "--threshold", "--depth", "--digits", "--rotate",
                                         "--window", "-o"};
    const char *a = argv[*i], *v = NULL;
    for (size_t k = 0; k < sizeof valued / sizeof valued[0]; k++)
        if (!strcmp(a, valued[k])) {
            if (*i + 1 >= argc) {
                fprintf(stderr, "tocher: %s needs a value\n", a);
                return -1;
            }
            v = argv[++*i];
        }
    if (!strcmp(a, "--gradients")) o->gradients = 1;
    else if (!strcmp(a, "--quads")) o->quads = 1;
    else if (!strcmp(a, "--no-midpoints")) o->midpoints = 0;
    else if (!strcmp(a, "--no-c0")) o->no_c0 = 1;
    else if (!strcmp(a, "--mesh") && tc_scene_mesh_kind_parse(v, &o->kind)) {
        list_known("mesh kind", v, kind_name_of, TC_SCENE_MESH_DM + 1);
        return -1;
    } else if (!strcmp(a, "--mesh")) return 0;
    else if (!strcmp(a, "--density")) return int_arg(a, v, 1, 1024, &o->density);
    else if (!strcmp(a, "--depth")) return int_arg(a, v, 0, 12, &o->max_depth);
    else if (!strcmp(a, "--digits")) return int_arg(a, v, 0, 17, &o->digits);
    else if (!strcmp(a, "--rotate")) return number_arg(a, v, &o->rotation);
    else if (!strcmp(a, "--window")) return sa->windowed = 1, window_arg(v, sa->window);
    else if (!strcmp(a, "--threshold")) return threshold_arg(v, &o->threshold);
    else if (!strcmp(a, "-o")) sa->out = v;
    else if (a[0] != '-' && !sa->name) sa->name = a;
    else {
        fprintf(stderr, "tocher: scene: unexpected argument '%s'\n\n", a);
        print_usage(stderr);
        return -1;
    }
    return 0;
}

static int scene_list(void) {
    for (int i = 0; i < TC_SCENE_COUNT; i++)
        printf("%-14s %s\n", tc_scene_name((tc_scene_id)i), tc_scene_summary((tc_scene_id)i));
    return 0;
}

/* `tocher scene NAME ...`: the scene's mesh and samples as a request (method
 * clough-tocher, or hermite with --quads), ready for `tocher ordinates` or the daemon. */
static int scene_command(int argc, char **argv) {
    tc_scene_mesh_opts o;
    scene_args sa = {NULL, NULL, 0, {0, 0, 0, 0}};
    tc_scene_mesh_opts_default(&o);
    if (argc == 3 && !strcmp(argv[2], "--list")) return scene_list();
    for (int i = 2; i < argc; i++)
        if (scene_option(argc, argv, &i, &o, &sa)) return EXIT_USAGE;
    const char *name = sa.name, *out = sa.out;
    tc_scene_id id;
    if (!name || tc_scene_parse(name, &id)) {
        list_known("scene", name, scene_name_of, TC_SCENE_COUNT);
        return EXIT_USAGE;
    }
    tc_scene s;
    tc_scene_mesh *m = NULL;
    if (sa.windowed) tc_scene_init_domain(&s, id, sa.window);
    else tc_scene_init(&s, id);
    int status = tc_scene_mesh_new(&s, &o, &m);
    if (status != TC_OK) {
        const char *why = tc_scene_mesh_opts_check(&o);
        fprintf(stderr, "tocher: scene %s: %s\n", name, status == TC_ELIMIT ? "the mesh would exceed 2^24 triangles" :
                        status == TC_ENOMEM ? "out of memory" : why ? why : "invalid options");
        return status == TC_ENOMEM ? EXIT_INTERNAL : EXIT_INPUT;
    }
    tc_options opt;
    tc_strbuf b;
    tc_options_default(&opt);
    for (int i = 0; o.quads && i < tc_method_count(); i++) /* what a quad mesh is for; triangle methods read it too */
        if (tc_method_quads_only((tc_method)i)) {
            opt.method = (tc_method)i;
            break;
        }
    tc_strbuf_init(&b);
    tc_json_request(&b, &m->desc, &opt);
    int rc = b.oom ? EXIT_INTERNAL : write_out(out, &b);
    if (b.oom) fputs("tocher: out of memory\n", stderr);
    tc_strbuf_free(&b);
    tc_scene_mesh_free(m);
    return rc;
}

int main(int argc, char **argv) {
    args a;
    if (argc > 1 && !strcmp(argv[1], "scene")) return scene_command(argc, argv);
    if (parse_args(argc, argv, &a) < 0) {
        print_usage(stderr);
        return EXIT_USAGE;
    }
    if (!strcmp(a.cmd, "help") || !strcmp(a.cmd, "--help") || !strcmp(a.cmd, "-h")) {
        print_usage(stdout);
        return 0;
    }
    if (!strcmp(a.cmd, "version") || !strcmp(a.cmd, "--version")) {
        printf("tocher %s\n", TC_VERSION);
        return 0;
    }
    int known = !strcmp(a.cmd, "ordinates") || !strcmp(a.cmd, "eval") || !strcmp(a.cmd, "render") ||
                !strcmp(a.cmd, "compare");
    if (!known || a.nfiles < 1 || (strcmp(a.cmd, "eval") && a.nfiles > 1)) {
        fprintf(stderr, "tocher: %s\n\n", known ? "missing or extra file arguments" : "unknown command");
        print_usage(stderr);
        return EXIT_USAGE;
    }
    return tc__leak_checked_exit(run(&a)); /* in a sanitizer build, core/leakcheck.c's check */
}
