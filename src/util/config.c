/* config.c - option value parsing (pure). */
#include "roadscan/util/config.h"

#include "roadscan/util/error.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <strings.h>

int rs_cfg_double(const char *key, const char *s, double lo, double hi, double *out, char *err, size_t n) {
  char *end;
  if (s == NULL || *s == '\0') {
    snprintf(err, n, "%s: missing value", key);
    return RS_E_INVAL;
  }
  errno = 0;
  double v = strtod(s, &end);
  if (errno != 0 || *end != '\0' || !isfinite(v)) {
    snprintf(err, n, "%s: '%s' is not a number", key, s);
    return RS_E_INVAL;
  }
  if (v < lo || v > hi) {
    snprintf(err, n, "%s: %s is out of range (%g to %g)", key, s, lo, hi);
    return RS_E_INVAL;
  }
  *out = v;
  return RS_OK;
}

int rs_cfg_long(const char *key, const char *s, long lo, long hi, long *out, char *err, size_t n) {
  char *end;
  if (s == NULL || *s == '\0') {
    snprintf(err, n, "%s: missing value", key);
    return RS_E_INVAL;
  }
  errno = 0;
  long v = strtol(s, &end, 10);
  if (errno != 0 || *end != '\0') {
    snprintf(err, n, "%s: '%s' is not an integer", key, s);
    return RS_E_INVAL;
  }
  if (v < lo || v > hi) {
    snprintf(err, n, "%s: %s is out of range (%ld to %ld)", key, s, lo, hi);
    return RS_E_INVAL;
  }
  *out = v;
  return RS_OK;
}

int rs_cfg_bool(const char *key, const char *s, bool *out, char *err, size_t n) {
  static const char *yes[] = {"1", "true", "yes", "on"}, *no[] = {"0", "false", "no", "off"};
  for (size_t i = 0; s && i < 4; i++) {
    if (strcasecmp(s, yes[i]) == 0) {
      *out = true;
      return RS_OK;
    }
    if (strcasecmp(s, no[i]) == 0) {
      *out = false;
      return RS_OK;
    }
  }
  snprintf(err, n, "%s: '%s' is not true or false (yes/no, on/off, 1/0)", key, s ? s : "");
  return RS_E_INVAL;
}

int rs_cfg_model(const char *key, const char *s, rs_model_t *out, char *err, size_t n) {
  const rs_model_t m = rs_model_from_name(s);
  if (m != RS_MODEL_UNKNOWN) {
    *out = m;
    return RS_OK;
  }
  snprintf(err, n, "%s: unknown sensor '%s' (known: %s)", key, s, rs_model_names());
  return RS_E_INVAL;
}
