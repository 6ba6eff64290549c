/* The app's signal dispositions (a C file: SIGXFSZ and SIG_IGN are the C library's). */
#include <signal.h>

/* Ignore SIGXFSZ, so that a write beyond the file-size limit (ulimit -f) fails with
   EFBIG ("File too large") instead of ending the process: the app then reports it and
   removes its temporary file like any other failed write. Returns 0, or -1 if the
   disposition could not be changed. */
int taylorode_app_ignore_file_size_signal(void) {
  return signal(SIGXFSZ, SIG_IGN) == SIG_ERR ? -1 : 0;
}
