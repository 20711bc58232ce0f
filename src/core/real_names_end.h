/* real_names_end.h - ends a body's use of real_names.h: its names are undefined, so that the
 * next inclusion (the other real type) defines them again. */
#undef R
#undef RN
#undef RC
#undef R_LOG
#undef R_EXP
#undef R_SQRT
#undef R_FLOOR
#undef R_FABS
#undef R_FMIN
#undef R_FMAX
#undef R_NEXTAFTER
#undef R_INF
#undef R_ONE_BELOW
