/* cancel.c — the stop request's flag (cancel.h). */
#include "cancel.h"

volatile sig_atomic_t sw_stop_request;
