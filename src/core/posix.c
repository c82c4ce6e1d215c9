/* POSIX services the Fortran standard lacks: what kind of file a path names, atomic rename,
 * durable writes (fsync), advisory locks that die with their process, and the signals a batch
 * scheduler sends. Each returns 0 or an errno value; nothing here prints or exits. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

/* File kinds of ffrf_file_kind, mirrored in ffrf_core_posix. */
enum { KIND_MISSING = 0, KIND_REGULAR = 1, KIND_DIRECTORY = 2, KIND_FIFO = 3, KIND_DEVICE = 4,
       KIND_OTHER = 5 };

/* Kind and size in bytes of the file `path` names (links followed); errno of stat() when it
 * cannot be inspected for another reason than its absence. */
int ffrf_file_kind(const char *path, int *kind, long long *size)
{
    struct stat st;
    *kind = KIND_MISSING;
    *size = 0;
    if (stat(path, &st) != 0) return errno == ENOENT || errno == ENOTDIR ? 0 : errno;
    *size = (long long)st.st_size;
    if (S_ISREG(st.st_mode)) *kind = KIND_REGULAR;
    else if (S_ISDIR(st.st_mode)) *kind = KIND_DIRECTORY;
    else if (S_ISFIFO(st.st_mode)) *kind = KIND_FIFO;
    else if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) *kind = KIND_DEVICE;
    else *kind = KIND_OTHER;
    return 0;
}

/* rename(2): replaces `to` atomically within one file system. */
int ffrf_rename(const char *from, const char *to)
{
    return rename(from, to) == 0 ? 0 : errno;
}

/* unlink(2); a missing file is not an error. */
int ffrf_unlink(const char *path)
{
    return unlink(path) == 0 || errno == ENOENT ? 0 : errno;
}

/* Flush a closed file's data to the device (open, fsync, close): a full disk or an I/O error
 * that the page cache hid until now is reported here. */
int ffrf_fsync_path(const char *path)
{
    int fd = open(path, O_RDONLY), status = 0;
    if (fd < 0) return errno;
    if (fsync(fd) != 0 && errno != EINVAL && errno != EROFS) status = errno;
    if (close(fd) != 0 && status == 0) status = errno;
    return status;
}

/* An exclusive advisory lock (flock) on `path`, created if missing. *fd is the descriptor that
 * holds it (-1 when not taken); the kernel releases it when the process ends, even by kill -9.
 * EWOULDBLOCK: another process holds it. */
int ffrf_lock_file(const char *path, int *fd)
{
    *fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (*fd < 0) return errno;
    if (flock(*fd, LOCK_EX | LOCK_NB) != 0) {
        int status = errno == EWOULDBLOCK ? EWOULDBLOCK : errno;
        close(*fd);
        *fd = -1;
        return status;
    }
    return 0;
}

/* Release a lock of ffrf_lock_file and remove its file (the remover holds the lock, so a
 * second run waiting on it never sees a half-removed lock as its own). */
int ffrf_unlock_file(const char *path, int fd)
{
    int status = 0;
    if (fd < 0) return 0;
    if (unlink(path) != 0 && errno != ENOENT) status = errno;
    flock(fd, LOCK_UN);
    close(fd);
    return status;
}

/* The system's words for an errno value. */
void ffrf_errno_text(int code, char *buffer, int length)
{
    if (length <= 0) return;
    snprintf(buffer, (size_t)length, "%s", strerror(code));
}

/* Signals a batch scheduler or a user sends to end a run: SIGTERM (scancel, the time limit),
 * SIGINT (Ctrl-C), SIGHUP (a closed terminal), SIGUSR1 and SIGXCPU (ahead of a time limit).
 * The handler only records the first one; the run checks it between steps (and a modal run
 * between bodies and between the solves of an eigen loop). A second SIGINT (Ctrl-C pressed
 * again) ends the run at once. */
static volatile sig_atomic_t pending_signal = 0;

static void record_signal(int signal_number)
{
    if (pending_signal == 0) {
        pending_signal = signal_number;
        return;
    }
    /* A second Ctrl-C while the first waits for the end of a step (or of a body's modes): the
     * user insists, so end the run at once, as without the handlers. Scheduler signals never
     * escalate: a repeated SIGTERM must not cut the clean end of the run short. */
    if (signal_number == SIGINT && pending_signal == SIGINT) {
        signal(SIGINT, SIG_DFL);
        raise(SIGINT);
    }
}

int ffrf_signals_install(void)
{
    const int signals[] = {SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU};
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = record_signal;
    sigemptyset(&action.sa_mask);
    for (size_t k = 0; k < sizeof signals / sizeof signals[0]; ++k)
        if (sigaction(signals[k], &action, NULL) != 0) return errno;
    return 0;
}

/* The first signal recorded since the handlers were installed (0: none). */
int ffrf_signal_pending(void)
{
    return (int)pending_signal;
}

/* Forget a recorded signal (tests). */
void ffrf_signal_clear(void)
{
    pending_signal = 0;
}

/* "SIGTERM" for SIGTERM, "signal N" otherwise. */
void ffrf_signal_name(int signal_number, char *buffer, int length)
{
    const char *name = signal_number == SIGTERM ? "SIGTERM" : signal_number == SIGINT ? "SIGINT"
        : signal_number == SIGHUP ? "SIGHUP" : signal_number == SIGUSR1 ? "SIGUSR1"
        : signal_number == SIGXCPU ? "SIGXCPU" : NULL;
    if (length <= 0) return;
    if (name) snprintf(buffer, (size_t)length, "%s", name);
    else snprintf(buffer, (size_t)length, "signal %d", signal_number);
}

/* ---- results files (issue 10, part 1): output locks, durable copies, full-disk signals ---- */

/* The lock of ffrf_lock_file, made safe against the removal of the lock file by the run that
 * held it: after taking the lock, the path must still name the locked file (same device and
 * inode), else another run removed it in between and the lock is taken again on the new file.
 * EWOULDBLOCK: another process holds it. */
int ffrf_lock_output(const char *path, int *fd)
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        struct stat held, named;
        int status = ffrf_lock_file(path, fd);
        if (status != 0) return status;
        if (fstat(*fd, &held) == 0 && stat(path, &named) == 0 && held.st_dev == named.st_dev
            && held.st_ino == named.st_ino)
            return 0;
        flock(*fd, LOCK_UN);
        close(*fd);
        *fd = -1;
    }
    return EWOULDBLOCK;
}

/* A process limited by RLIMIT_FSIZE (ulimit -f) is killed by SIGXFSZ when a write passes the
 * limit; ignored, the write fails with EFBIG and the run reports it like a full disk. */
int ffrf_ignore_file_size_signal(void)
{
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = SIG_IGN;
    sigemptyset(&action.sa_mask);
    return sigaction(SIGXFSZ, &action, NULL) == 0 ? 0 : errno;
}

/* Copy the file `from` to `to` (created or truncated, mode 0644) and fsync `to`: the bytes are
 * on the device when this returns 0. Errno of the first failure otherwise (`to` is then
 * incomplete: the caller removes it). */
int ffrf_copy_file(const char *from, const char *to)
{
    char buffer[1 << 16];
    int in = open(from, O_RDONLY | O_CLOEXEC), out, status = 0;
    if (in < 0) return errno;
    out = open(to, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (out < 0) {
        status = errno;
        close(in);
        return status;
    }
    for (;;) {
        ssize_t got = read(in, buffer, sizeof buffer), done = 0;
        if (got < 0) {
            if (errno == EINTR) continue;
            status = errno;
            break;
        }
        if (got == 0) break;
        while (done < got) {
            ssize_t put = write(out, buffer + done, (size_t)(got - done));
            if (put < 0) {
                if (errno == EINTR) continue;
                status = errno;
                break;
            }
            done += put;
        }
        if (status != 0) break;
    }
    if (status == 0 && fsync(out) != 0 && errno != EINVAL && errno != EROFS) status = errno;
    if (close(out) != 0 && status == 0) status = errno;
    close(in);
    return status;
}

/* fsync the folder that holds `path`, so that a rename into it survives a power cut. Errors of
 * file systems that cannot sync a folder are ignored. */
int ffrf_fsync_folder_of(const char *path)
{
    char folder[4096];
    const char *slash = strrchr(path, '/');
    int fd, status = 0;
    if (slash == NULL) snprintf(folder, sizeof folder, ".");
    else if (slash == path) snprintf(folder, sizeof folder, "/");
    else snprintf(folder, sizeof folder, "%.*s", (int)(slash - path), path);
    fd = open(folder, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 0;
    if (fsync(fd) != 0 && errno != EINVAL && errno != EROFS && errno != EBADF) status = errno;
    close(fd);
    return status;
}

/* Make the signals of ffrf_signals_install restart interrupted system calls (SA_RESTART): a
 * signal that arrives while a mesh or case file is read must not fail that read with EINTR;
 * the run ends at its next check of ffrf_signal_pending instead. */
int ffrf_signals_restart_calls(void)
{
    const int signals[] = {SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU};
    for (size_t k = 0; k < sizeof signals / sizeof signals[0]; ++k) {
        struct sigaction action;
        if (sigaction(signals[k], NULL, &action) != 0) return errno;
        action.sa_flags |= SA_RESTART;
        if (sigaction(signals[k], &action, NULL) != 0) return errno;
    }
    return 0;
}
