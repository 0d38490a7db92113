/* config.h - strict parsing of option values, with messages that name the
 * option. (Pure; start-up only.) */
#ifndef ROADSCAN_CONFIG_H
#define ROADSCAN_CONFIG_H

#include "roadscan/sensor/sensor.h"

#include <stdbool.h>
#include <stddef.h>

/* Whole string must be a finite number within [lo, hi]. RS_OK or RS_E_INVAL
 * with err = "--speed: 'abc' is not a number" / "... must be between ...". */
int rs_cfg_double(const char *key, const char *s, double lo, double hi, double *out, char *err, size_t n);
int rs_cfg_long(const char *key, const char *s, long lo, long hi, long *out, char *err, size_t n);
/* true/false, yes/no, on/off, 1/0 (any case). */
int rs_cfg_bool(const char *key, const char *s, bool *out, char *err, size_t n);

/* A sensor model by name; err = "--model: unknown sensor 'x' (known: ...)". */
int rs_cfg_model(const char *key, const char *s, rs_model_t *out, char *err, size_t n);

#endif
