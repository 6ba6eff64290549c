/* The app's signal dispositions (a C file: the handlers and SIG_IGN are the C library's). */
#include <signal.h>
#include <string.h>
#include <unistd.h>

/* Ignore SIGXFSZ, so that a write beyond the file-size limit (ulimit -f) fails with
   EFBIG ("File too large") instead of ending the process: the app then reports it and
   removes its temporary file like any other failed write. Returns 0, or -1 if the
   disposition could not be changed. */
int taylorode_app_ignore_file_size_signal(void) {
  return signal(SIGXFSZ, SIG_IGN) == SIG_ERR ? -1 : 0;
}

/* The temporary files of the outputs the run may be writing, removed when SIGINT,
   SIGTERM or SIGHUP ends it (their destinations stay as they were). */
#define TEMPORARIES 16
#define PATH_BYTES 4096
static char temporaries[TEMPORARIES][PATH_BYTES];
static volatile sig_atomic_t temporary_count = 0;

/* unlink(2) and raise(3) are async-signal-safe: remove the temporary files, then end
   the process as the signal would have, with its default action. */
static void remove_temporaries(int sig) {
  for (int k = 0; k < temporary_count; k++) unlink(temporaries[k]);
  signal(sig, SIG_DFL);
  raise(sig);
}

/* Remember path (a temporary file the run may create) for removal on SIGINT, SIGTERM or
   SIGHUP; the first call installs the handlers (a signal ignored at start stays
   ignored). Returns 0, or -1 when there is no room or a handler could not be installed. */
int taylorode_app_remove_on_signal(const char *path) {
  static const int signals[] = {SIGINT, SIGTERM, SIGHUP};
  size_t length = strlen(path);
  if (temporary_count >= TEMPORARIES || length >= PATH_BYTES) return -1;
  memcpy(temporaries[temporary_count], path, length + 1);
  temporary_count = temporary_count + 1;
  if (temporary_count > 1) return 0;
  for (size_t k = 0; k < sizeof signals / sizeof signals[0]; k++) {
    struct sigaction action, previous;
    if (sigaction(signals[k], NULL, &previous) != 0) return -1;
    if (previous.sa_handler == SIG_IGN) continue;
    memset(&action, 0, sizeof action);
    action.sa_handler = remove_temporaries;
    sigemptyset(&action.sa_mask);
    if (sigaction(signals[k], &action, NULL) != 0) return -1;
  }
  return 0;
}
