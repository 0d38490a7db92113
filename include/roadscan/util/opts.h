/* opts.h - one table of options per program: it drives the command line, the
 * INI file, --help and the man page (--man), so they cannot disagree.
 *
 * Design. A program describes each option once in a const rs_opt_t table:
 * its name (the long option and the INI key), its type, the range of values
 * it accepts, where the value goes (an offset into one settings struct the
 * program owns), its help text and, when the value it starts with is not
 * what a user should read, the default to show. RS_OPT_SECTION rows open a
 * group: its name is the INI section the following options belong to, its
 * help the heading in --help and in the man page. The defaults shown are the
 * settings struct's values when rs_opts_init runs (the libraries' own
 * defaults), so no default is written twice.
 *
 * The same rows describe parameter tables without a program (the tracker's
 * and the simulator's knobs): rs_opt_set applies one NAME=VALUE to a struct.
 *
 * Start-up only, main thread; no allocation (string values are copied into
 * the context's arena, which the caller owns, so they outlive the INI
 * parser's buffers). */
#ifndef ROADSCAN_OPTS_H
#define ROADSCAN_OPTS_H

#include "roadscan/util/error.h"

#include <getopt.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#define RS_OPTS_MAX 96       /* rows of one program's table */
#define RS_OPTS_ARENA 16384  /* bytes of string values one run may keep */
#define RS_OPTS_DEF_LEN 80   /* a default as text */

typedef enum {
  RS_OPT_SECTION, /* a heading; name = INI section ("" = command line only), help = its title */
  RS_OPT_FLAG,    /* bool: no value on the command line; true/false (yes/no, on/off, 1/0) in a file */
  RS_OPT_BOOL,    /* bool: a value on the command line too */
  RS_OPT_STR,     /* const char * */
  RS_OPT_DOUBLE,  /* double within [lo, hi]; stored times scale */
  RS_OPT_FLOAT,   /* float within [lo, hi]; stored times scale */
  RS_OPT_INT,     /* int, a whole number within [lo, hi] */
  RS_OPT_CHOICE,  /* int: the index of the value among choices ("a|b|c") */
  RS_OPT_MODEL,   /* rs_model_t: a sensor model's name */
  RS_OPT_FUNC,    /* fn(target, key, value): anything else (a pose, a line, NAME=VALUE) */
} rs_opt_type_t;

enum {
  RS_OPT_REPEAT = 1u,  /* may be given several times (fn sees each) */
  RS_OPT_CLI = 2u,     /* command line only: not a key of the file */
  RS_OPT_NODEF = 4u,   /* no default shown */
};

/* key names the option in messages ("--eps", "site.ini: [cluster] eps"). */
typedef int (*rs_opt_fn)(void *target, const char *key, const char *value, char *err, size_t n);

typedef struct {
  rs_opt_type_t type;
  const char *name;      /* --name and the INI key */
  char short_name;       /* -o, or 0 */
  const char *arg;       /* the value's name in the help: FILE, X, ... (NULL for flags) */
  size_t off;            /* the target: offset into the settings struct */
  double lo, hi;         /* numbers: accepted range */
  double scale;          /* stored = given x scale (0 means 1) */
  const char *choices;   /* RS_OPT_CHOICE: "a|b|c" */
  rs_opt_fn fn;          /* RS_OPT_FUNC; with RS_OPT_STR a check of the text before it is kept */
  unsigned flags;
  const char *implied;   /* a value the command line may leave out ("--stats" alone: this; shown as
                            "--stats [NAME]"); NULL: a value is required */
  const char *def;       /* the default to show; NULL: the target's value at rs_opts_init */
  const char *help;
} rs_opt_t;

/* Rows, for readable tables (T = the settings struct's type, f = its field). */
#define RS_OPT_HEAD(sec, title) {.type = RS_OPT_SECTION, .name = (sec), .help = (title)}
#define RS_OPT_FLAG_(nm, T, f, h) {.type = RS_OPT_FLAG, .name = (nm), .off = offsetof(T, f), .help = (h)}
#define RS_OPT_STR_(nm, a, T, f, h) {.type = RS_OPT_STR, .name = (nm), .arg = (a), .off = offsetof(T, f), .help = (h)}
#define RS_OPT_DBL_(nm, a, T, f, l, u, h) \
  {.type = RS_OPT_DOUBLE, .name = (nm), .arg = (a), .off = offsetof(T, f), .lo = (l), .hi = (u), .help = (h)}
#define RS_OPT_FLT_(nm, a, T, f, l, u, h) \
  {.type = RS_OPT_FLOAT, .name = (nm), .arg = (a), .off = offsetof(T, f), .lo = (l), .hi = (u), .help = (h)}
#define RS_OPT_INT_(nm, a, T, f, l, u, h) \
  {.type = RS_OPT_INT, .name = (nm), .arg = (a), .off = offsetof(T, f), .lo = (l), .hi = (u), .help = (h)}
/* Rows several programs share. */
#define RS_OPT_OUTPUT_(a, T, f, h) \
  {.type = RS_OPT_STR, .name = "output", .short_name = 'o', .arg = (a), .off = offsetof(T, f), .help = (h)}
#define RS_OPT_FORCE_MODEL_(nm, T, f)                                                                   \
  {.type = RS_OPT_MODEL, .name = (nm), .arg = "NAME", .off = offsetof(T, f), .def = "detected from the packets", \
   .help = "force the sensor model"}
#define RS_OPT_CALIB_(T, f) RS_OPT_STR_("calibration", "FILE", T, f, "per-unit calibration (ROS velodyne YAML)")

/* What a program says about itself. */
typedef struct {
  const char *prog;      /* roadscand */
  int man_section;       /* 1, or 8 for the daemon */
  const char *summary;   /* one line: what it does */
  const char *synopsis;  /* usage lines, one per \n, without the program's name */
  const char *about;     /* paragraphs of description ("\n\n" between them); may be NULL */
  const char *epilog;    /* exit status and the like; may be NULL */
  bool config_file;      /* --config FILE reads the INI file first, the command line overrides it */
  int min_args, max_args; /* arguments that are not options (max_args < 0: any number) */
  const rs_opt_t *opts;
  int n;
} rs_opts_spec_t;

typedef struct {
  const rs_opts_spec_t *spec;
  void *base;                        /* the settings struct */
  unsigned char given[RS_OPTS_MAX];  /* times each row was set */
  char defs[RS_OPTS_MAX][RS_OPTS_DEF_LEN];
  char arena[RS_OPTS_ARENA];
  size_t used;
  struct option lopts[RS_OPTS_MAX + 5];
  char err[RS_ERRMSG_SIZE]; /* (room for a parameter table's names: rs_opt_set) */
} rs_opts_t;

typedef enum { RS_OPTS_RUN = 0, RS_OPTS_EXIT = 1, RS_OPTS_ERROR = 2 } rs_opts_result_t;

/* Checks the table (names unique, ranges ordered, choices present: a
 * programming error returns RS_E_INVAL with o->err) and records the
 * defaults from base. */
int rs_opts_init(rs_opts_t *o, const rs_opts_spec_t *spec, void *base);

/* The config file (when the spec allows it and --config is given, wherever it
 * is), then the command line. --help, --man and --version print and give
 * RS_OPTS_EXIT. RS_OPTS_ERROR: o->err names the option and the problem.
 * *first_arg (optional): the index of the first argument that is not an
 * option (getopt order). */
rs_opts_result_t rs_opts_parse(rs_opts_t *o, int argc, char **argv, int *first_arg);

/* The start of every program: rs_opts_init, rs_opts_parse and the argument count. Returns -1 to
 * go on (*first: the first argument that is not an option), else the exit status: 0 after --help,
 * --man or --version, 2 after a usage error, said on stderr as "prog: message". */
int rs_opts_start(rs_opts_t *o, const rs_opts_spec_t *spec, void *base, int argc, char **argv, int *first);

/* An INI file: keys are option names in their section; an unknown key, a key
 * in the wrong section, a key twice (unless repeatable), a NUL byte or a line
 * too long for the parser are refused with the file and line. RS_OK or
 * RS_E_INVAL/RS_E_IO with o->err. */
int rs_opts_read_file(rs_opts_t *o, const char *path);
/* The same from an open stream (rewound; name in the messages). */
int rs_opts_read_stream(rs_opts_t *o, FILE *f, const char *name);

/* Sets one option by name (as a file would); key names it in messages. */
int rs_opts_set(rs_opts_t *o, const char *name, const char *value, const char *key);

/* How many times the option was given (0: it keeps its default). */
int rs_opts_given(const rs_opts_t *o, const char *name);

void rs_opts_help(const rs_opts_t *o, FILE *out);
void rs_opts_man(const rs_opts_t *o, FILE *out);

/* A parameter table without a program: sets field `name` of base from value
 * (numbers, flags and choices; no strings). RS_E_INVAL with err naming the
 * parameter, or listing the known ones (prefix: "tracking parameter"). */
int rs_opt_set(const rs_opt_t *tab, int n, void *base, const char *prefix, const char *name, const char *value,
               char *err, size_t en);
/* The table's names, space-separated, into buf. */
void rs_opt_names(const rs_opt_t *tab, int n, char *buf, size_t size);

#endif
