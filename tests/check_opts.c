/* check_opts - the option table: command line, INI file, --help and --man
 * from one table; parameter tables; every program's table. */
#include "roadscan/perception/cluster.h"
#include "roadscan/util/error.h"
#include "roadscan/util/opts.h"
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  const char *pcap, *name;
  double speed, hz;
  float gain;
  int port, method;
  bool fast, loop, on;
  rs_model_t model;
  int pair[2];
  int lines;
  const char *stats;
} set_t;

static int parse_pair(void *t, const char *key, const char *v, char *err, size_t n) {
  int a, b;
  char tail;
  if (sscanf(v, "%dx%d%c", &a, &b, &tail) != 2) {
    snprintf(err, n, "%s: '%s' is not AxB", key, v);
    return RS_E_INVAL;
  }
  ((int *)t)[0] = a;
  ((int *)t)[1] = b;
  return RS_OK;
}

static int count_line(void *t, const char *key, const char *v, char *err, size_t n) {
  (void)key;
  (void)v;
  (void)err;
  (void)n;
  ++*(int *)t;
  return RS_OK;
}

#define T set_t
static const rs_opt_t table[] = {
    RS_OPT_HEAD("source", "Source"),
    {.type = RS_OPT_STR, .name = "pcap", .short_name = 'p', .arg = "FILE", .off = offsetof(T, pcap),
     .help = "a capture"},
    RS_OPT_DBL_("speed", "X", T, speed, 0.5, 10.0, "replay speed"),
    RS_OPT_FLAG_("fast", T, fast, "flat out"),
    RS_OPT_FLAG_("loop", T, loop, "again"),
    RS_OPT_INT_("port", "N", T, port, 1, 65535, "data port"),
    {.type = RS_OPT_DOUBLE, .name = "rpm", .arg = "N", .off = offsetof(T, hz), .lo = 300, .hi = 1200,
     .scale = 1.0 / 60.0, .help = "rotation rate"},
    RS_OPT_HEAD("cluster", "Clustering"),
    {.type = RS_OPT_CHOICE, .name = "cluster", .arg = "METHOD", .off = offsetof(T, method),
     .choices = "none|fspc|dbscan", .help = "the method"},
    RS_OPT_FLT_("gain", "G", T, gain, 0.0, 2.0, "a float"),
    {.type = RS_OPT_BOOL, .name = "on", .arg = "on|off", .off = offsetof(T, on), .help = "a switch"},
    {.type = RS_OPT_FUNC, .name = "window", .arg = "AxB", .off = offsetof(T, pair), .fn = parse_pair,
     .def = "5x11", .help = "a window"},
    {.type = RS_OPT_FUNC, .name = "line", .arg = "L", .off = offsetof(T, lines), .fn = count_line,
     .flags = RS_OPT_REPEAT, .help = "repeatable"},
    {.type = RS_OPT_MODEL, .name = "model", .arg = "NAME", .off = offsetof(T, model), .def = "detected",
     .help = "the sensor"},
    RS_OPT_HEAD("lcm", "LCM"),
    {.type = RS_OPT_STR, .name = "stats", .arg = "NAME", .off = offsetof(T, stats), .implied = "STATS",
     .flags = RS_OPT_CLI, .help = "also statistics"},
    RS_OPT_STR_("name", "ID", T, name,
                "a long help text that goes on and on so that it has to be wrapped over several lines of the "
                "help, never wider than a hundred columns, whatever the words are"),
};
#undef T

static const rs_opts_spec_t spec = {.prog = "prog",
                                    .summary = "a test program",
                                    .synopsis = "[options] FILE\n--other",
                                    .about = "First paragraph.\n\nSecond paragraph.",
                                    .epilog = "Exit status: 0.",
                                    .config_file = true,
                                    .opts = table,
                                    .n = (int)(sizeof table / sizeof table[0])};

static set_t st;
static rs_opts_t o;

static void fresh(void) {
  st = (set_t){.speed = 1.0, .hz = 10.0, .port = 2368, .gain = 0.5f, .name = "roadscan", .method = 1};
  ck_assert_int_eq(rs_opts_init(&o, &spec, &st), RS_OK);
}

static rs_opts_result_t parse(int argc, const char **argv, int *first) {
  return rs_opts_parse(&o, argc, (char **)argv, first);
}

START_TEST(t_command_line) {
  fresh();
  const char *argv[] = {"prog", "--speed", "2.5", "--fast", "-p", "a.pcap", "--port=2000", "--rpm", "1200",
                        "--cluster", "dbscan", "--gain", "1.5", "--on", "off", "--window", "3x9", "--line", "x",
                        "--line", "y", "--model", "VLP-16", "--stats", "FILE1", "FILE2", NULL};
  int first = -1;
  ck_assert_int_eq(parse(26, argv, &first), RS_OPTS_RUN);
  ck_assert_double_eq(st.speed, 2.5);
  ck_assert(st.fast && !st.loop);
  ck_assert_str_eq(st.pcap, "a.pcap");
  ck_assert_int_eq(st.port, 2000);
  ck_assert_double_eq_tol(st.hz, 20.0, 1e-12); /* stored times the scale */
  ck_assert_int_eq(st.method, 2);
  ck_assert_float_eq(st.gain, 1.5f);
  ck_assert(!st.on);
  ck_assert_int_eq(st.pair[0], 3);
  ck_assert_int_eq(st.pair[1], 9);
  ck_assert_int_eq(st.lines, 2);
  ck_assert_int_eq(st.model, RS_MODEL_VLP16);
  ck_assert_str_eq(st.stats, "STATS"); /* given without its value */
  ck_assert_int_eq(rs_opts_given(&o, "line"), 2);
  ck_assert_int_eq(rs_opts_given(&o, "speed"), 1);
  ck_assert_int_eq(rs_opts_given(&o, "loop"), 0);
  ck_assert_int_eq(rs_opts_given(&o, "no-such"), 0);
  ck_assert_int_eq(first, 24); /* getopt moved the arguments to the end */
  ck_assert_str_eq(argv[first], "FILE1");
  /* an optional value is taken when attached */
  fresh();
  const char *argv2[] = {"prog", "--stats=OTHER", NULL};
  ck_assert_int_eq(parse(2, argv2, &first), RS_OPTS_RUN);
  ck_assert_str_eq(st.stats, "OTHER");
}
END_TEST

/* each bad value is refused with the option's name and the problem; the target keeps its value */
START_TEST(t_command_line_errors) {
  static const struct {
    const char *opt, *val, *msg;
  } bad[] = {
      {"--speed", "11", "--speed: 11 is out of range (0.5 to 10)"},
      {"--speed", "fast", "--speed: 'fast' is not a number"},
      {"--port", "1.5", "--port: '1.5' is not an integer"},
      {"--cluster", "kmeans", "--cluster: 'kmeans' is not one of none, fspc, dbscan"},
      {"--on", "maybe", "--on: 'maybe' is not true or false"},
      {"--window", "3", "--window: '3' is not AxB"},
      {"--model", "HDL-64E", "--model: unknown sensor 'HDL-64E'"},
      {"--rpm", "60", "--rpm: 60 is out of range (300 to 1200)"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    fresh();
    const char *argv[] = {"prog", bad[i].opt, bad[i].val, NULL};
    ck_assert_int_eq(parse(3, argv, NULL), RS_OPTS_ERROR);
    ck_assert_msg(strstr(o.err, bad[i].msg) != NULL, "%s %s: %s", bad[i].opt, bad[i].val, o.err);
    ck_assert_double_eq(st.speed, 1.0);
    ck_assert_int_eq(st.port, 2368);
    ck_assert_int_eq(st.method, 1);
  }
  fresh();
  const char *unknown[] = {"prog", "--speeed", "2", NULL};
  ck_assert_int_eq(parse(3, unknown, NULL), RS_OPTS_ERROR);
  ck_assert_ptr_nonnull(strstr(o.err, "unknown option '--speeed'"));
  const char *shortu[] = {"prog", "-x", NULL};
  ck_assert_int_eq(parse(2, shortu, NULL), RS_OPTS_ERROR);
  ck_assert_ptr_nonnull(strstr(o.err, "unknown option '-x'"));
  const char *missing[] = {"prog", "--speed", NULL};
  ck_assert_int_eq(parse(2, missing, NULL), RS_OPTS_ERROR);
  ck_assert_ptr_nonnull(strstr(o.err, "--speed: missing value"));
  const char *flagval[] = {"prog", "--fast=yes", NULL};
  ck_assert_int_eq(parse(2, flagval, NULL), RS_OPTS_ERROR); /* a flag takes no value on the command line */
}
END_TEST

static const char *write_file(const char *name, const char *text, size_t len) {
  const char *path = tu_tmp(name);
  FILE *f = fopen(path, "wb");
  ck_assert_ptr_nonnull(f);
  fwrite(text, 1, len, f);
  fclose(f);
  return path;
}

START_TEST(t_config_file) {
  fresh();
  static const char good[] = "# a site\n[source]\npcap = site.pcap\nspeed = 4\nloop = true\n"
                             "[cluster]\ncluster = none\nline = a\nline = b\n[lcm]\nname = north gate\n";
  const char *path = write_file("opts-good.ini", good, strlen(good));
  char cfgarg[600];
  snprintf(cfgarg, sizeof cfgarg, "--config=%s", path);
  const char *argv[] = {"prog", "--speed", "2", cfgarg, NULL};
  ck_assert_int_eq(parse(4, argv, NULL), RS_OPTS_RUN);
  ck_assert_str_eq(st.pcap, "site.pcap"); /* copied: outlives the parser's buffers */
  ck_assert_double_eq(st.speed, 2.0);    /* the command line overrides the file, wherever --config is */
  ck_assert(st.loop);
  ck_assert_int_eq(st.method, 0);
  ck_assert_int_eq(st.lines, 2); /* a repeatable key may be given twice */
  ck_assert_str_eq(st.name, "north gate");
  static const struct {
    const char *text, *msg;
  } bad[] = {
      {"[source]\nspeed = 20\n", "opts-bad.ini:2: [source] speed: 20 is out of range"},
      {"[cluster]\nspeed = 2\n", "opts-bad.ini:2: [cluster] speed: 'speed' belongs in section [source]"},
      {"[source]\nspeeed = 2\n", "unknown key 'speeed'"},
      {"[lcm]\nstats = X\n", "unknown key 'stats'"}, /* command line only */
      {"[source]\nport = 1\nport = 2\n", "opts-bad.ini:3: [source] port: given twice in the file"},
      {"[source]\nfast = perhaps\n", "[source] fast: 'perhaps' is not true or false"},
      {"speed = 2\n", "'speed' belongs in section [source]"},
      {"[source\n", "opts-bad.ini:1: not an INI line"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    fresh();
    const char *p = write_file("opts-bad.ini", bad[i].text, strlen(bad[i].text));
    ck_assert_int_eq(rs_opts_read_file(&o, p), RS_E_INVAL);
    ck_assert_msg(strstr(o.err, bad[i].msg) != NULL, "%s: %s", bad[i].text, o.err);
  }
  fresh();
  const char *nul = write_file("opts-nul.ini", "[lcm]\nname = a\0b\n", 17);
  ck_assert_int_eq(rs_opts_read_file(&o, nul), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(o.err, "opts-nul.ini:2: a NUL byte"));
  char longl[400] = "[lcm]\nname = ";
  memset(longl + strlen(longl), 'x', 250);
  const char *lp = write_file("opts-long.ini", longl, strlen(longl));
  ck_assert_int_eq(rs_opts_read_file(&o, lp), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(o.err, "opts-long.ini:2: the line is longer than"));
  ck_assert_int_eq(rs_opts_read_file(&o, tu_tmp("opts-none.ini")), RS_E_IO);
  ck_assert_ptr_nonnull(strstr(o.err, "cannot read"));
  /* a bad file stops the command line */
  fresh();
  const char *p = write_file("opts-bad.ini", "[source]\nspeed = 20\n", 20);
  const char *argv2[] = {"prog", "--config", p, NULL};
  ck_assert_int_eq(parse(3, argv2, NULL), RS_OPTS_ERROR);
  ck_assert_ptr_nonnull(strstr(o.err, "out of range"));
}
END_TEST

static char *capture_output(void (*fn)(const rs_opts_t *, FILE *)) {
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  fn(&o, f);
  fclose(f);
  return buf;
}

START_TEST(t_help) {
  fresh();
  /* the defaults shown are those the settings had at init, not what a parse set */
  const char *argv[] = {"prog", "--speed", "3", NULL};
  ck_assert_int_eq(parse(3, argv, NULL), RS_OPTS_RUN);
  char *h = capture_output(rs_opts_help);
  ck_assert_ptr_nonnull(strstr(h, "usage: prog [options] FILE\n       prog --other\n"));
  ck_assert_ptr_nonnull(strstr(h, "First paragraph.\n\nSecond paragraph."));
  ck_assert_ptr_nonnull(strstr(h, "\nSource [source]\n"));
  ck_assert_ptr_nonnull(strstr(h, "  --speed X             replay speed (default 1; 0.5 to 10)\n"));
  ck_assert_ptr_nonnull(strstr(h, "  -p, --pcap FILE       a capture\n"));
  ck_assert_ptr_nonnull(strstr(h, "--rpm N               rotation rate (default 600; 300 to 1200)"));
  ck_assert_ptr_nonnull(strstr(h, "the method (one of none, fspc, dbscan; default fspc)"));
  ck_assert_ptr_nonnull(strstr(h, "a window (default 5x11)"));
  ck_assert_ptr_nonnull(strstr(h, "repeatable"));
  ck_assert_ptr_nonnull(strstr(h, "--stats [NAME]"));
  ck_assert_ptr_nonnull(strstr(h, "one of VLP-16,"));
  ck_assert_ptr_nonnull(strstr(h, "--config FILE"));
  ck_assert_ptr_nonnull(strstr(h, "Exit status: 0."));
  ck_assert_ptr_null(strstr(h, "default 3;"));
  /* wrapped: no line wider than 100 columns */
  for (char *line = h; *line;) {
    size_t len = strcspn(line, "\n");
    ck_assert_msg(len <= 100, "%.*s", (int)len, line);
    line += len + (line[len] == '\n');
  }
  free(h);
  char *m = capture_output(rs_opts_man);
  ck_assert(strncmp(m, ".TH \"prog\" 1 ", 13) == 0);
  ck_assert_ptr_nonnull(strstr(m, "\n.SH NAME\nprog \\- a test program\n"));
  ck_assert_ptr_nonnull(strstr(m, "\n.SS \"Source [source]\"\n"));
  ck_assert_ptr_nonnull(strstr(m, "\n.TP\n.B \\-\\-speed X\nreplay speed (default 1; 0.5 to 10)\n"));
  ck_assert_ptr_nonnull(strstr(m, "\n.SH NOTES\n"));
  /* every option has its entry; no text line starts with a control character */
  int tp = 0;
  for (char *line = m; *line;) {
    size_t len = strcspn(line, "\n");
    if (strncmp(line, ".TP", 3) == 0) tp++;
    if (line[0] == '\'') ck_abort_msg("line starts with a quote: %.*s", (int)len, line);
    line += len + (line[len] == '\n');
  }
  ck_assert_int_eq(tp, 14 + 4); /* the table's 14 options, --config, --help, --man, --version */
  free(m);
}
END_TEST

/* a table with a mistake is refused at init, naming the row */
START_TEST(t_bad_tables) {
  static const rs_opt_t dup[] = {RS_OPT_FLAG_("a", set_t, fast, "x"), RS_OPT_FLAG_("a", set_t, loop, "y")};
  static const rs_opt_t range[] = {RS_OPT_DBL_("a", "X", set_t, speed, 2.0, 1.0, "x")};
  static const rs_opt_t builtin[] = {RS_OPT_FLAG_("help", set_t, fast, "x")};
  static const rs_opt_t noarg[] = {{.type = RS_OPT_INT, .name = "a", .off = offsetof(set_t, port), .hi = 3}};
  static const rs_opt_t nochoices[] = {
      {.type = RS_OPT_CHOICE, .name = "a", .arg = "X", .off = offsetof(set_t, method)}};
  const rs_opt_t *tabs[] = {dup, range, builtin, noarg, nochoices};
  const int ns[] = {2, 1, 1, 1, 1};
  for (int i = 0; i < 5; i++) {
    rs_opts_spec_t sp = {.prog = "bad", .summary = "s", .opts = tabs[i], .n = ns[i]};
    ck_assert_int_eq(rs_opts_init(&o, &sp, &st), RS_E_INVAL);
    ck_assert_ptr_nonnull(strstr(o.err, "is not valid or not unique"));
  }
}
END_TEST

/* a parameter table without a program (the tracker's knobs, the scene's) */
START_TEST(t_parameter_table) {
  set_t s = {.speed = 1.0};
  char err[256];
  ck_assert_int_eq(rs_opt_set(table, spec.n, &s, "test parameter", "speed", "5", err, sizeof err), RS_OK);
  ck_assert_double_eq(s.speed, 5.0);
  ck_assert_int_eq(rs_opt_set(table, spec.n, &s, "test parameter", "speed", "50", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "test parameter speed: 50 is out of range"));
  ck_assert_int_eq(rs_opt_set(table, spec.n, &s, "test parameter", "sped", "5", err, sizeof err), RS_E_INVAL);
  ck_assert_ptr_nonnull(strstr(err, "no test parameter 'sped'; there are: pcap speed fast"));
  /* text values need a program's arena */
  ck_assert_int_eq(rs_opt_set(table, spec.n, &s, "test parameter", "pcap", "x", err, sizeof err), RS_E_INVAL);
  char names[256];
  rs_opt_names(table, 3, names, sizeof names);
  ck_assert_str_eq(names, "pcap speed"); /* headings are not names */
}
END_TEST

/* every program: --help, --man and --version from its table; an unknown option is a usage error */
START_TEST(t_programs) {
  static const char *progs[] = {"roadscand",        "roadscan-sim",   "roadscan-learn",      "roadscan-bench",
                                "roadscan-eval",    "roadscan-export", "roadscan-listen",    "roadscan-render",
                                "roadscan-scenestats", "roadscan-synth"};
  char cmd[256];
  const char *out;
  for (size_t i = 0; i < sizeof progs / sizeof progs[0]; i++) {
    snprintf(cmd, sizeof cmd, "./%s --help", progs[i]);
    ck_assert_msg(tu_exec(cmd, &out) == 0, "%s", cmd);
    ck_assert_msg(strncmp(out, "usage: ", 7) == 0, "%s: %.80s", cmd, out);
    snprintf(cmd, sizeof cmd, "./%s --man", progs[i]);
    ck_assert_msg(tu_exec(cmd, &out) == 0, "%s", cmd);
    ck_assert_msg(strncmp(out, ".TH \"", 5) == 0 && strstr(out, "\n.SH OPTIONS\n"), "%s", cmd);
    snprintf(cmd, sizeof cmd, "./%s --version", progs[i]);
    ck_assert_msg(tu_exec(cmd, &out) == 0 && strstr(out, RS_VERSION), "%s", cmd);
    snprintf(cmd, sizeof cmd, "./%s --no-such-option", progs[i]);
    ck_assert_msg(tu_exec(cmd, &out) == 2 && strstr(out, "unknown option '--no-such-option'"), "%s: %s", cmd, out);
  }
  /* the argument counts the programs declare */
  ck_assert_int_eq(tu_exec("./roadscan-eval a b", &out), 2);
  ck_assert_msg(strstr(out, "roadscan-eval: 1 argument missing (usage: roadscan-eval CAPTURE TRUTH PRED") != NULL, "%s",
                out);
  /* a learning rule's share out of its range is refused by name, before the capture is read */
  ck_assert_int_eq(tu_exec("./roadscan-learn no-such.pcap -o no-such.bg --leaves 2", &out), 2);
  ck_assert_msg(strstr(out, "roadscan-learn: --leaves: 2 is out of range (0 to 1)") != NULL, "%s", out);
  ck_assert_int_eq(tu_exec("./roadscan-listen --quiet extra", &out), 2);
  ck_assert_msg(strstr(out, "roadscan-listen: unexpected argument 'extra' (see --help)") != NULL, "%s", out);
  ck_assert_int_eq(tu_exec("./roadscan-export a.pcap b.pcap --frame 1 -o x", &out), 2);
  ck_assert_msg(strstr(out, "unexpected argument 'b.pcap'") != NULL, "%s", out);
  /* the daemon's clustering defaults, written as text in its table, are the clustering module's */
  rs_cluster_cfg_t c;
  rs_cluster_cfg_default(&c);
  char want[160];
  snprintf(want, sizeof want, "default fspc %g, fspc-adaptive %g, dbscan %g, ccl %g", (double)c.fspc.eps,
           (double)c.adaptive.eps_max, (double)c.dbscan.eps, (double)c.ccl.eps);
  ck_assert_int_eq(tu_exec("./roadscand --help", &out), 0);
  char *flat = strdup(out); /* the help wraps and aligns: compare with every run of blanks as one space */
  for (char *p = flat, *q = flat;; p++) {
    if (*p == '\n' || *p == ' ') {
      *q++ = ' ';
      while (p[1] == ' ' || p[1] == '\n') p++;
    } else if (!(*q++ = *p)) break;
  }
  ck_assert_msg(strstr(flat, want) != NULL, "%s", want);
  snprintf(want, sizeof want, "--window HxW the FSPC window (the largest with fspc-adaptive), odd numbers (default %dx%d)",
           c.fspc.win_h, c.fspc.win_w);
  ck_assert_msg(strstr(flat, want) != NULL, "%s", want);
  ck_assert(c.adaptive.win_h == c.fspc.win_h && c.adaptive.win_w == c.fspc.win_w);
  snprintf(want, sizeof want, "(default %d; 1 to 255)", c.fspc.min_pts);
  ck_assert_msg(strstr(flat, want) != NULL, "%s", want);
  ck_assert(c.dbscan.min_pts == c.fspc.min_pts && c.adaptive.max_min_pts == c.fspc.min_pts);
  free(flat);
}
END_TEST

int main(void) {
  Suite *s = suite_create("opts");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, t_command_line);
  tcase_add_test(tc, t_command_line_errors);
  tcase_add_test(tc, t_config_file);
  tcase_add_test(tc, t_help);
  tcase_add_test(tc, t_bad_tables);
  tcase_add_test(tc, t_parameter_table);
  tcase_add_test(tc, t_programs);
  suite_add_tcase(s, tc);
  return tu_run(s);
}
