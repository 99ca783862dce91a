/* cancel.h — the stop request that the long loops of models/ poll (building a tree over a
 * large mesh obstacle, counting intersecting pairs), so that a SIGINT or SIGTERM ends them
 * within a fraction of a second.
 *
 * The flag lives on models' floor so that models never call up into the run loop: the run
 * loop sets it (sim/sim.c: sw_interrupt, safe from a signal handler) and clears it; models and
 * the OBJ reader (sim/input/obj.c) only read it. */
#ifndef SW_CANCEL_H
#define SW_CANCEL_H

#include <signal.h>

/* The signal of the pending stop request, 0 if none (models/cancel.c). */
extern volatile sig_atomic_t sw_stop_request;

/* The pending stop request's signal, 0 if none. */
static inline int sw_cancelled(void) { return sw_stop_request; }

#endif
