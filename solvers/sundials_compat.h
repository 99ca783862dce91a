/* sundials_compat.h — the few places where SUNDIALS 6.x (Debian: 6.4.1) and 7.x differ, in one
 * header: the real and boolean type names, SUNContext_Create's communicator argument, and how
 * error messages are routed (6.x: per integrator, CVodeSetErrHandlerFn / IDASetErrHandlerFn;
 * 7.x: per context, SUNContext_PushErrHandler).  Only the 6.x branch is compiled and tested
 * here; the 7.x branch follows the SUNDIALS 7 API and is kept this small on purpose. */
#ifndef SW_SUNDIALS_COMPAT_H
#define SW_SUNDIALS_COMPAT_H

#include <stdio.h>

#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_types.h>

#include "sinew.h"

#if SUNDIALS_VERSION_MAJOR >= 7

typedef sunrealtype sw_real;
typedef sunbooleantype sw_bool;

static inline int sw_sun_context(SUNContext *ctx) { return SUNContext_Create(SUN_COMM_NULL, ctx); }

/* data: a char[SW_ERRSZ] that receives the last error message. */
static inline void sw_sun_errfn(int line, const char *func, const char *file, const char *msg,
                                SUNErrCode code, void *data, SUNContext ctx) {
  (void)line, (void)file, (void)ctx;
  snprintf(data, SW_ERRSZ, "%s: %s (error %d)", func ? func : "?", msg ? msg : "", (int)code);
}

/* Send the error messages of the integrator mem (context ctx) to buf instead of stderr. */
#define SW_SUN_ROUTE_ERRORS(set_handler_fn, mem, ctx, buf)                                      \
  ((void)(mem), SUNContext_ClearErrHandlers(ctx),                                              \
   SUNContext_PushErrHandler((ctx), sw_sun_errfn, (buf)))

#else /* SUNDIALS 6.x */

typedef realtype sw_real;
typedef booleantype sw_bool;

static inline int sw_sun_context(SUNContext *ctx) { return SUNContext_Create(NULL, ctx); }

/* data: a char[SW_ERRSZ] that receives the last error message; warnings (code > 0, e.g.
 * "t + h = t") are dropped. */
static inline void sw_sun_errfn(int code, const char *module, const char *function, char *msg,
                                void *data) {
  if (code >= 0) return;
  snprintf(data, SW_ERRSZ, "%s %s: %s", module ? module : "?", function ? function : "?",
           msg ? msg : "");
}

#define SW_SUN_ROUTE_ERRORS(set_handler_fn, mem, ctx, buf)                                      \
  ((void)(ctx), set_handler_fn((mem), sw_sun_errfn, (buf)))

#endif

#endif
