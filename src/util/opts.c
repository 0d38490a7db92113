/* opts.c - the option table: command line, INI file, --help, --man.
 * (Start-up only; see opts.h.) */
#include "roadscan/util/opts.h"

#include "roadscan/sensor/sensor.h"
#include "roadscan/util/config.h"
#include "roadscan/util/error.h"

#include <ini.h>

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#define LONG_BASE 1000 /* getopt values of the table's rows: LONG_BASE + row */
enum { B_CONFIG = LONG_BASE + RS_OPTS_MAX, B_HELP, B_MAN, B_VERSION };
#define INI_LINE_MAX 198 /* inih's line buffer (INI_MAX_LINE, 200) less the newline and its NUL */
#define HELP_COL 24
#define HELP_WIDTH 100

static void *target(void *base, const rs_opt_t *r) { return (char *)base + r->off; }

static bool takes_value(const rs_opt_t *r) { return r->type != RS_OPT_FLAG; }

/* the n-th name of "a|b|c" into buf; false past the end */
static bool choice_at(const char *choices, int k, char *buf, size_t size) {
  const char *p = choices;
  for (int i = 0; i < k; i++) {
    p = strchr(p, '|');
    if (p == NULL) return false;
    p++;
  }
  size_t len = strcspn(p, "|");
  if (len >= size) len = size - 1;
  memcpy(buf, p, len);
  buf[len] = '\0';
  return true;
}

/* Applies one value. o (optional) keeps strings; value NULL: a flag on the command line. */
static int apply(rs_opts_t *o, const rs_opt_t *r, void *base, const char *key, const char *value, char *err,
                 size_t n) {
  void *t = target(base, r);
  const double scale = r->scale != 0 ? r->scale : 1.0;
  double d;
  long l;
  if (value == NULL && r->type != RS_OPT_FLAG) {
    snprintf(err, n, "%s: missing value", key);
    return RS_E_INVAL;
  }
  switch (r->type) {
  case RS_OPT_FLAG:
    if (value == NULL) {
      *(bool *)t = true;
      return RS_OK;
    }
    return rs_cfg_bool(key, value, (bool *)t, err, n);
  case RS_OPT_BOOL: return rs_cfg_bool(key, value, (bool *)t, err, n);
  case RS_OPT_STR: {
    if (r->fn && r->fn(t, key, value, err, n) != RS_OK) return RS_E_INVAL; /* a check of the text */
    if (o == NULL) {
      snprintf(err, n, "%s: text values need a program's options", key);
      return RS_E_INVAL;
    }
    const size_t len = strlen(value) + 1;
    if (len > sizeof o->arena - o->used) {
      snprintf(err, n, "%s: the options take more than %zu bytes", key, sizeof o->arena);
      return RS_E_NOMEM;
    }
    *(const char **)t = memcpy(o->arena + o->used, value, len);
    o->used += len;
    return RS_OK;
  }
  case RS_OPT_DOUBLE:
    if (rs_cfg_double(key, value, r->lo, r->hi, &d, err, n) != RS_OK) return RS_E_INVAL;
    *(double *)t = d * scale;
    return RS_OK;
  case RS_OPT_FLOAT:
    if (rs_cfg_double(key, value, r->lo, r->hi, &d, err, n) != RS_OK) return RS_E_INVAL;
    *(float *)t = (float)(d * scale);
    return RS_OK;
  case RS_OPT_INT:
    if (rs_cfg_long(key, value, (long)r->lo, (long)r->hi, &l, err, n) != RS_OK) return RS_E_INVAL;
    *(int *)t = (int)l;
    return RS_OK;
  case RS_OPT_CHOICE: {
    char name[64];
    for (int k = 0; choice_at(r->choices, k, name, sizeof name); k++)
      if (strcmp(name, value) == 0) {
        *(int *)t = k;
        return RS_OK;
      }
    int used = snprintf(err, n, "%s: '%s' is not one of ", key, value);
    for (int k = 0; used >= 0 && (size_t)used < n && choice_at(r->choices, k, name, sizeof name); k++)
      used += snprintf(err + used, n - (size_t)used, "%s%s", k ? ", " : "", name);
    return RS_E_INVAL;
  }
  case RS_OPT_MODEL: return rs_cfg_model(key, value, (rs_model_t *)t, err, n);
  case RS_OPT_FUNC: return r->fn(t, key, value, err, n) == RS_OK ? RS_OK : RS_E_INVAL;
  case RS_OPT_SECTION: break;
  }
  snprintf(err, n, "%s: not an option", key);
  return RS_E_INVAL;
}

/* the value as it would be written (the default, shown in help) */
static void format_value(const rs_opt_t *r, const void *base, char *buf, size_t n) {
  const void *t = (const char *)base + r->off;
  const double scale = r->scale != 0 ? r->scale : 1.0;
  buf[0] = '\0';
  if (r->def) {
    snprintf(buf, n, "%s", r->def);
    return;
  }
  if (r->flags & RS_OPT_NODEF) return;
  switch (r->type) {
  case RS_OPT_BOOL: snprintf(buf, n, "%s", *(const bool *)t ? "on" : "off"); break;
  case RS_OPT_STR:
    if (*(const char *const *)t) snprintf(buf, n, "%s", *(const char *const *)t);
    break;
  case RS_OPT_DOUBLE: snprintf(buf, n, "%.10g", *(const double *)t / scale); break;
  case RS_OPT_FLOAT: snprintf(buf, n, "%.7g", (double)*(const float *)t / scale); break;
  case RS_OPT_INT: snprintf(buf, n, "%d", *(const int *)t); break;
  case RS_OPT_CHOICE:
    if (!choice_at(r->choices, *(const int *)t, buf, n)) buf[0] = '\0';
    break;
  case RS_OPT_MODEL:
    if (*(const rs_model_t *)t != RS_MODEL_UNKNOWN) snprintf(buf, n, "%s", rs_model_name(*(const rs_model_t *)t));
    break;
  case RS_OPT_FLAG:
  case RS_OPT_FUNC:
  case RS_OPT_SECTION: break;
  }
}

static int find(const rs_opt_t *tab, int n, const char *name) {
  for (int i = 0; i < n; i++)
    if (tab[i].type != RS_OPT_SECTION && strcmp(tab[i].name, name) == 0) return i;
  return -1;
}

/* the section a row belongs to ("" before the first heading) */
static const char *section_of(const rs_opt_t *tab, int i) {
  for (int k = i; k >= 0; k--)
    if (tab[k].type == RS_OPT_SECTION) return tab[k].name;
  return "";
}

int rs_opts_init(rs_opts_t *o, const rs_opts_spec_t *spec, void *base) {
  memset(o->given, 0, sizeof o->given);
  o->spec = spec;
  o->base = base;
  o->used = 0;
  o->err[0] = '\0';
  if (spec->n > RS_OPTS_MAX) {
    snprintf(o->err, sizeof o->err, "%s: %d options, at most %d", spec->prog, spec->n, RS_OPTS_MAX);
    return RS_E_INVAL;
  }
  static const char *builtin[] = {"config", "help", "man", "version"};
  for (int i = 0; i < spec->n; i++) {
    const rs_opt_t *r = &spec->opts[i];
    o->defs[i][0] = '\0';
    if (r->type == RS_OPT_SECTION) continue;
    bool bad = r->name == NULL || r->name[0] == '\0' || find(spec->opts, i, r->name) >= 0 ||
               ((r->type == RS_OPT_DOUBLE || r->type == RS_OPT_FLOAT || r->type == RS_OPT_INT) && !(r->lo <= r->hi)) ||
               (r->type == RS_OPT_CHOICE && r->choices == NULL) || (r->type == RS_OPT_FUNC && r->fn == NULL) ||
               (takes_value(r) && r->arg == NULL);
    for (size_t b = 0; !bad && b < sizeof builtin / sizeof builtin[0]; b++) bad = strcmp(builtin[b], r->name) == 0;
    if (bad) {
      snprintf(o->err, sizeof o->err, "%s: option row %d (%s) is not valid or not unique", spec->prog, i,
               r->name ? r->name : "(no name)");
      return RS_E_INVAL;
    }
    format_value(r, base, o->defs[i], sizeof o->defs[i]);
  }
  return RS_OK;
}

int rs_opts_set(rs_opts_t *o, const char *name, const char *value, const char *key) {
  const int i = find(o->spec->opts, o->spec->n, name);
  if (i < 0) {
    snprintf(o->err, sizeof o->err, "%s: not an option of %s", key, o->spec->prog);
    return RS_E_INVAL;
  }
  int rc = apply(o, &o->spec->opts[i], o->base, key, value, o->err, sizeof o->err);
  if (rc == RS_OK && o->given[i] < UINT8_MAX) o->given[i]++;
  return rc;
}

int rs_opts_given(const rs_opts_t *o, const char *name) {
  const int i = find(o->spec->opts, o->spec->n, name);
  return i < 0 ? 0 : o->given[i];
}

/* ---- the INI file ---- */

typedef struct {
  rs_opts_t *o;
  const char *path;
  bool failed;
  unsigned char seen[RS_OPTS_MAX];
} ini_ctx_t;

static int on_ini(void *user, const char *section, const char *name, const char *value) {
  ini_ctx_t *c = user;
  rs_opts_t *o = c->o;
  if (c->failed) return 0;
  char key[384];
  if (section[0]) snprintf(key, sizeof key, "[%s] %s", section, name);
  else snprintf(key, sizeof key, "%s", name);
  c->failed = true;
  const int i = find(o->spec->opts, o->spec->n, name);
  if (i < 0 || (o->spec->opts[i].flags & RS_OPT_CLI)) {
    snprintf(o->err, sizeof o->err, "%s: unknown key '%s' (the keys are the option names of --help)", key, name);
    return 0;
  }
  const char *want = section_of(o->spec->opts, i);
  if (strcmp(want, section) != 0) {
    if (want[0]) snprintf(o->err, sizeof o->err, "%s: '%s' belongs in section [%s]", key, name, want);
    else snprintf(o->err, sizeof o->err, "%s: '%s' belongs before any section", key, name);
    return 0;
  }
  /* a key given twice is a mistake (the last would win silently), but for the repeatable ones */
  if (c->seen[i] && !(o->spec->opts[i].flags & RS_OPT_REPEAT)) {
    snprintf(o->err, sizeof o->err, "%s: given twice in the file", key);
    return 0;
  }
  c->seen[i] = 1;
  if (rs_opts_set(o, name, value, key) != RS_OK) return 0;
  c->failed = false;
  return 1;
}

int rs_opts_read_file(rs_opts_t *o, const char *path) {
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    snprintf(o->err, sizeof o->err, "%s: cannot read: %s", path, strerror(errno));
    return RS_E_IO;
  }
  const int rc = rs_opts_read_stream(o, f, path);
  fclose(f);
  return rc;
}

int rs_opts_read_stream(rs_opts_t *o, FILE *f, const char *path) {
  ini_ctx_t c = {.o = o, .path = path, .failed = false};
  /* what inih would silently cut: a NUL byte (the value ends there), a line longer than its buffer */
  int line = 1, col = 0, ch;
  while ((ch = fgetc(f)) != EOF) {
    if (ch == '\n') {
      line++;
      col = 0;
      continue;
    }
    if (ch == '\0') snprintf(o->err, sizeof o->err, "%s:%d: a NUL byte (not a text file)", path, line);
    else if (++col > INI_LINE_MAX)
      snprintf(o->err, sizeof o->err, "%s:%d: the line is longer than %d characters", path, line, INI_LINE_MAX);
    else continue;
    return RS_E_INVAL;
  }
  rewind(f);
  const int rc = ini_parse_file(f, on_ini, &c);
  if (c.failed) { /* the file and line first (inih stops at the first line its handler refuses) */
    char why[sizeof o->err];
    memcpy(why, o->err, sizeof why);
    /* the path at most half the room, the reason the rest (a parameter table's names are long) */
    const int at = snprintf(o->err, sizeof o->err, "%.*s:%d: ", (int)(sizeof o->err / 2), path, rc);
    if (at > 0 && (size_t)at < sizeof o->err) {
      const size_t room = sizeof o->err - (size_t)at, n = strnlen(why, room - 1);
      memcpy(o->err + at, why, n);
      o->err[(size_t)at + n] = '\0';
    }
    return RS_E_INVAL;
  }
  if (rc != 0) {
    snprintf(o->err, sizeof o->err, "%s:%d: not an INI line (expected [section] or key = value)", path, rc);
    return RS_E_INVAL;
  }
  return RS_OK;
}

/* ---- the command line ---- */

rs_opts_result_t rs_opts_parse(rs_opts_t *o, int argc, char **argv, int *first_arg) {
  const rs_opts_spec_t *s = o->spec;
  char shorts[2 * RS_OPTS_MAX + 2] = ":";
  size_t ns = 1;
  int nl = 0;
  for (int i = 0; i < s->n; i++) {
    const rs_opt_t *r = &s->opts[i];
    if (r->type == RS_OPT_SECTION) continue;
    o->lopts[nl++] = (struct option){r->name,
                                     !takes_value(r) ? no_argument : r->implied ? optional_argument : required_argument,
                                     NULL, LONG_BASE + i};
    if (r->short_name) {
      shorts[ns++] = r->short_name;
      if (takes_value(r)) shorts[ns++] = ':';
    }
  }
  shorts[ns] = '\0';
  if (s->config_file) o->lopts[nl++] = (struct option){"config", required_argument, NULL, B_CONFIG};
  o->lopts[nl++] = (struct option){"help", no_argument, NULL, B_HELP};
  o->lopts[nl++] = (struct option){"man", no_argument, NULL, B_MAN};
  o->lopts[nl++] = (struct option){"version", no_argument, NULL, B_VERSION};
  o->lopts[nl] = (struct option){NULL, 0, NULL, 0};
  /* the config file first, wherever it is on the command line */
  for (int i = 1; s->config_file && i < argc && strcmp(argv[i], "--") != 0; i++) {
    const char *path = NULL;
    if (strcmp(argv[i], "--config") == 0 && i + 1 < argc) path = argv[++i];
    else if (strncmp(argv[i], "--config=", 9) == 0) path = argv[i] + 9;
    if (path && rs_opts_read_file(o, path) != RS_OK) return RS_OPTS_ERROR;
  }
  optind = 0; /* GNU: start again (the tests parse several command lines) */
  opterr = 0;
  int c;
  while ((c = getopt_long(argc, argv, shorts, o->lopts, NULL)) != -1) {
    const char *arg = argv[optind - 1];
    if (c == '?') {
      if (optopt) snprintf(o->err, sizeof o->err, "unknown option '-%c' (see --help)", optopt);
      else snprintf(o->err, sizeof o->err, "unknown option '%s' (see --help)", arg);
      return RS_OPTS_ERROR;
    }
    if (c == ':') {
      snprintf(o->err, sizeof o->err, "%s: missing value", arg);
      return RS_OPTS_ERROR;
    }
    if (c == B_CONFIG) continue;
    if (c == B_HELP) {
      rs_opts_help(o, stdout);
      return RS_OPTS_EXIT;
    }
    if (c == B_MAN) {
      rs_opts_man(o, stdout);
      return RS_OPTS_EXIT;
    }
    if (c == B_VERSION) {
      printf("%s %s\n", s->prog, RS_VERSION);
      return RS_OPTS_EXIT;
    }
    int i = c - LONG_BASE;
    if (c < LONG_BASE)
      for (i = 0; i < s->n && !(s->opts[i].type != RS_OPT_SECTION && s->opts[i].short_name == c); i++) {
      }
    if (i < 0 || i >= s->n) {
      snprintf(o->err, sizeof o->err, "unknown option '%s' (see --help)", arg);
      return RS_OPTS_ERROR;
    }
    char key[80];
    snprintf(key, sizeof key, "--%s", s->opts[i].name);
    const char *value = takes_value(&s->opts[i]) ? (optarg ? optarg : s->opts[i].implied) : NULL;
    if (rs_opts_set(o, s->opts[i].name, value, key) != RS_OK) return RS_OPTS_ERROR;
  }
  if (first_arg) *first_arg = optind;
  return RS_OPTS_RUN;
}

int rs_opts_start(rs_opts_t *o, const rs_opts_spec_t *spec, void *base, int argc, char **argv, int *first) {
  int f = argc;
  rs_opts_result_t pr = RS_OPTS_ERROR;
  if (rs_opts_init(o, spec, base) == RS_OK) pr = rs_opts_parse(o, argc, argv, &f);
  if (pr == RS_OPTS_EXIT) return 0;
  if (pr == RS_OPTS_RUN) {
    const int n = argc - f;
    if (spec->max_args >= 0 && n > spec->max_args)
      snprintf(o->err, sizeof o->err, "unexpected argument '%s' (see --help)", argv[f + spec->max_args]);
    else if (n < spec->min_args)
      snprintf(o->err, sizeof o->err, "%d argument%s missing (usage: %s %.*s)", spec->min_args - n,
               spec->min_args - n > 1 ? "s" : "", spec->prog, (int)strcspn(spec->synopsis ? spec->synopsis : "", "\n"),
               spec->synopsis ? spec->synopsis : "");
    else {
      *first = f;
      return -1;
    }
  }
  fprintf(stderr, "%s: %s\n", spec->prog, o->err);
  return 2;
}

/* ---- help and man page ---- */

/* the option as written: "-o, --output FILE" */
static void option_text(const rs_opt_t *r, char *buf, size_t n) {
  int used = 0;
  if (r->short_name) used = snprintf(buf, n, "-%c, ", r->short_name);
  if (!takes_value(r)) snprintf(buf + used, n - (size_t)used, "--%s", r->name);
  else if (r->implied) snprintf(buf + used, n - (size_t)used, "--%s [%s]", r->name, r->arg);
  else snprintf(buf + used, n - (size_t)used, "--%s %s", r->name, r->arg);
}

/* help text with what the table knows: choices, default, range */
static void full_help(const rs_opts_t *o, int i, char *buf, size_t n) {
  const rs_opt_t *r = &o->spec->opts[i];
  int used = snprintf(buf, n, "%s", r->help ? r->help : "");
  char tail[512] = "";
  int t = 0;
  if (r->type == RS_OPT_CHOICE) {
    char name[64];
    t += snprintf(tail + t, sizeof tail - (size_t)t, "one of ");
    for (int k = 0; choice_at(r->choices, k, name, sizeof name) && (size_t)t < sizeof tail; k++)
      t += snprintf(tail + t, sizeof tail - (size_t)t, "%s%s", k ? ", " : "", name);
  }
  if (r->type == RS_OPT_MODEL) t += snprintf(tail, sizeof tail, "one of %s", rs_model_names());
  if (o->defs[i][0] && (size_t)t < sizeof tail)
    t += snprintf(tail + t, sizeof tail - (size_t)t, "%sdefault %s", t ? "; " : "", o->defs[i]);
  if ((r->type == RS_OPT_DOUBLE || r->type == RS_OPT_FLOAT || r->type == RS_OPT_INT) && (size_t)t < sizeof tail)
    t += snprintf(tail + t, sizeof tail - (size_t)t, "%s%.10g to %.10g", t ? "; " : "", r->lo, r->hi);
  if ((r->flags & RS_OPT_REPEAT) && (size_t)t < sizeof tail)
    t += snprintf(tail + t, sizeof tail - (size_t)t, "%srepeatable", t ? "; " : "");
  if (t > 0 && used >= 0 && (size_t)used < n) snprintf(buf + used, n - (size_t)used, "%s(%s)", used ? " " : "", tail);
}

/* words of text from column col, lines up to HELP_WIDTH, continuation lines at indent */
static void wrap(FILE *out, const char *text, int col, int indent) {
  const char *p = text;
  while (*p) {
    if (*p == '\n') {
      fprintf(out, "\n%*s", indent, "");
      col = indent;
      p++;
      continue;
    }
    const size_t len = strcspn(p, " \n");
    if (col > indent && col + 1 + (int)len > HELP_WIDTH) {
      fprintf(out, "\n%*s", indent, "");
      col = indent;
    } else if (col > indent) {
      fputc(' ', out);
      col++;
    }
    fprintf(out, "%.*s", (int)len, p);
    col += (int)len;
    p += len;
    while (*p == ' ') p++;
  }
  fputc('\n', out);
}

void rs_opts_help(const rs_opts_t *o, FILE *out) {
  const rs_opts_spec_t *s = o->spec;
  const char *syn = s->synopsis ? s->synopsis : "[options]";
  for (int line = 0; *syn; line++) {
    const size_t len = strcspn(syn, "\n");
    fprintf(out, "%s %s %.*s\n", line ? "      " : "usage:", s->prog, (int)len, syn);
    syn += len + (syn[len] == '\n');
  }
  fprintf(out, "\n");
  wrap(out, s->summary, 0, 0);
  if (s->about) {
    for (const char *p = s->about; *p;) {
      const char *end = strstr(p, "\n\n");
      const size_t len = end ? (size_t)(end - p) : strlen(p);
      char para[2048];
      snprintf(para, sizeof para, "%.*s", (int)len, p);
      fprintf(out, "\n");
      wrap(out, para, 0, 0);
      p += len + (end ? 2 : 0);
    }
  }
  if (s->config_file)
    fprintf(out, "\nEvery option but --config can also be set in the config file (INI): the key is the option's\n"
                 "name in the section shown in brackets; flags take true/false. The command line overrides the "
                 "file.\n  --config FILE         read options from FILE first\n");
  char opt[128], help[1024];
  if (s->n > 0 && s->opts[0].type != RS_OPT_SECTION) fprintf(out, "\nOptions\n");
  for (int i = 0; i < s->n; i++) {
    const rs_opt_t *r = &s->opts[i];
    if (r->type == RS_OPT_SECTION) {
      fprintf(out, "\n%s", r->help);
      if (s->config_file && r->name[0]) fprintf(out, " [%s]", r->name);
      fprintf(out, "\n");
      continue;
    }
    option_text(r, opt, sizeof opt);
    full_help(o, i, help, sizeof help);
    const int w = fprintf(out, "  %s", opt);
    if (w + 2 > HELP_COL) fprintf(out, "\n%*s", HELP_COL, "");
    else fprintf(out, "%*s", HELP_COL - w, "");
    wrap(out, help, HELP_COL, HELP_COL);
  }
  fprintf(out, "\n  --help                this text; --man: the manual page (troff); --version\n");
  if (s->epilog) {
    fprintf(out, "\n");
    wrap(out, s->epilog, 0, 0);
  }
}

/* troff text: backslashes, hyphens (minus signs in options), and a leading dot or quote escaped */
static void roff(FILE *out, const char *text) {
  bool line_start = true;
  for (const char *p = text; *p; p++) {
    if (line_start && (*p == '.' || *p == '\'')) fputs("\\&", out);
    if (*p == '\\') fputs("\\e", out);
    else if (*p == '-') fputs("\\-", out);
    else fputc(*p, out);
    line_start = *p == '\n';
  }
}

static void roff_paragraphs(FILE *out, const char *text) {
  for (const char *p = text; *p;) {
    const char *end = strstr(p, "\n\n");
    const size_t len = end ? (size_t)(end - p) : strlen(p);
    char para[2048];
    snprintf(para, sizeof para, "%.*s", (int)len, p);
    for (char *q = para; *q; q++)
      if (*q == '\n') *q = ' ';
    fputs(".PP\n", out);
    roff(out, para);
    fputc('\n', out);
    p += len + (end ? 2 : 0);
  }
}

void rs_opts_man(const rs_opts_t *o, FILE *out) {
  const rs_opts_spec_t *s = o->spec;
  fprintf(out, ".TH \"");
  roff(out, s->prog);
  fprintf(out, "\" %d \"\" \"roadscan %s\" \"roadscan\"\n.SH NAME\n", s->man_section ? s->man_section : 1, RS_VERSION);
  roff(out, s->prog);
  fputs(" \\- ", out);
  roff(out, s->summary);
  fputs("\n.SH SYNOPSIS\n", out);
  const char *syn = s->synopsis ? s->synopsis : "[options]";
  while (*syn) {
    const size_t len = strcspn(syn, "\n");
    char line[512];
    snprintf(line, sizeof line, "%.*s", (int)len, syn);
    fputs(".B ", out);
    roff(out, s->prog);
    fputc(' ', out);
    roff(out, line);
    fputs("\n.br\n", out);
    syn += len + (syn[len] == '\n');
  }
  fputs(".SH DESCRIPTION\n", out);
  roff_paragraphs(out, s->summary);
  if (s->about) roff_paragraphs(out, s->about);
  if (s->config_file)
    roff_paragraphs(out, "Every option but --config can also be set in an INI file read with --config FILE: the key "
                         "is the option's name, in the section given with each group below; flags take true or "
                         "false. The command line overrides the file.");
  fputs(".SH OPTIONS\n", out);
  char opt[128], help[1024];
  for (int i = 0; i < s->n; i++) {
    const rs_opt_t *r = &s->opts[i];
    if (r->type == RS_OPT_SECTION) {
      fputs(".SS \"", out);
      roff(out, r->help);
      if (s->config_file && r->name[0]) fprintf(out, " [%s]", r->name);
      fputs("\"\n", out);
      continue;
    }
    option_text(r, opt, sizeof opt);
    full_help(o, i, help, sizeof help);
    fputs(".TP\n.B ", out);
    roff(out, opt);
    fputc('\n', out);
    for (char *q = help; *q; q++)
      if (*q == '\n') *q = ' ';
    roff(out, help);
    fputc('\n', out);
  }
  if (s->config_file) fputs(".TP\n.B \\-\\-config FILE\nread options from FILE first\n", out);
  fputs(".TP\n.B \\-\\-help\nprint the options and exit\n.TP\n.B \\-\\-man\nprint this manual page (troff) and "
        "exit\n.TP\n.B \\-\\-version\nprint the version and exit\n",
        out);
  if (s->epilog) {
    fputs(".SH NOTES\n", out);
    roff_paragraphs(out, s->epilog);
  }
}

/* ---- parameter tables ---- */

int rs_opt_set(const rs_opt_t *tab, int n, void *base, const char *prefix, const char *name, const char *value,
               char *err, size_t en) {
  const int i = find(tab, n, name);
  if (i < 0) {
    size_t used = (size_t)snprintf(err, en, "no %s '%s'; there are:", prefix, name);
    for (int k = 0; k < n && used < en; k++)
      if (tab[k].type != RS_OPT_SECTION) used += (size_t)snprintf(err + used, en - used, " %s", tab[k].name);
    return RS_E_INVAL;
  }
  char key[128];
  snprintf(key, sizeof key, "%s %s", prefix, name);
  return apply(NULL, &tab[i], base, key, value, err, en);
}

void rs_opt_names(const rs_opt_t *tab, int n, char *buf, size_t size) {
  size_t used = 0;
  if (size) buf[0] = '\0';
  for (int k = 0; k < n && used < size; k++)
    if (tab[k].type != RS_OPT_SECTION)
      used += (size_t)snprintf(buf + used, size - used, "%s%s", used ? " " : "", tab[k].name);
}
