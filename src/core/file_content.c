/* The extent of a file's content, found without reading it whole: the offset after its last
 * byte that is neither NUL nor blank (space, TAB, CR, LF), and whether NUL bytes (or holes of a
 * sparse file) come after it. A file padded to 2 GB after a valid header is so read as its
 * header only. Returns 0 or an errno value; nothing here prints. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

static int is_padding(char c)
{
    return c == '\0' || c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

int ffrf_content_end(const char *path, long long *end, int *nul_after)
{
    char buffer[1 << 16];
    struct stat st;
    off_t data_end, pos;
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK), status = 0;
    *end = 0;
    *nul_after = 0;
    if (fd < 0) return errno;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        status = errno != 0 ? errno : EINVAL;
        close(fd);
        return status;
    }
    data_end = st.st_size;
#ifdef SEEK_HOLE
    /* the end of the last data extent: a trailing hole is NUL bytes never stored */
    {
        off_t at = 0, last = 0;
        for (;;) {
            off_t data = lseek(fd, at, SEEK_DATA), hole;
            if (data < 0) {
                if (errno != ENXIO) last = st.st_size; /* no SEEK_DATA here: read it all */
                break;
            }
            hole = lseek(fd, data, SEEK_HOLE);
            if (hole < 0) {
                last = st.st_size;
                break;
            }
            last = hole;
            if (hole >= st.st_size) break;
            at = hole;
        }
        if (last < st.st_size) *nul_after = 1;
        data_end = last;
    }
#endif
    /* back from data_end, a chunk at a time, to the last byte of content */
    pos = data_end;
    while (pos > 0) {
        off_t start = pos > (off_t)sizeof buffer ? pos - (off_t)sizeof buffer : 0;
        ssize_t got = pread(fd, buffer, (size_t)(pos - start), start);
        if (got < 0) {
            if (errno == EINTR) continue;
            status = errno;
            break;
        }
        if (got != pos - start) {
            status = EIO;
            break;
        }
        for (ssize_t k = got - 1; k >= 0; --k) {
            if (!is_padding(buffer[k])) {
                *end = (long long)(start + k + 1);
                close(fd);
                return 0;
            }
            if (buffer[k] == '\0') *nul_after = 1;
        }
        pos = start;
    }
    close(fd);
    return status;
}
