/* test_vdb_sandbox.c - the .vdb reader's child is a program of its own, brume-openvdb-reader,
 * started with posix_spawn, never a fork of this process (io/grid_sandbox.c says why: a
 * fork copies the locks other threads hold, and AddressSanitizer's allocator then left the
 * child blocked for good); the bytes of a grid given from memory reach it whole. */
#include "test.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>

#include "core/error.h"
#include "io/grid_io.h"
#include "io/grid_sandbox.h"
#include "io/vdb_path.h"

static atomic_int forks;
static void count_fork(void) { atomic_fetch_add(&forks, 1); }

static void need_openvdb(void)
{
    if (!grid_have_openvdb()) {
        printf("skipped: no OpenVDB in this build\n");
        exit(77);
    }
}

static atomic_bool stop;
/* What a renderer's threads do while a sequence reads ahead: allocate and free, always. */
static void *churn(void *arg)
{
    (void)arg;
    uint64_t x = 1;
    while (!atomic_load(&stop)) {
        x = x * 6364136223846793005ULL + 1442695040888963407ULL;
        void *p = malloc(16 + (size_t)(x >> 52));
        free(p);
    }
    return NULL;
}

/* Eight reads of data/box_fog_21cube.vdb while two threads allocate without pause: each gives
 * the grid, and no fork happens in this process (pthread_atfork's prepare handlers run at
 * every fork, never at posix_spawn's exec). */
TEST(vdb_reader_is_a_program_not_a_fork)
{
    need_openvdb();
    ASSERT_EQ_INT(pthread_atfork(count_fork, NULL, NULL), 0);
    pthread_t t[2];
    for (int i = 0; i < 2; i++)
        ASSERT_EQ_INT(pthread_create(&t[i], NULL, churn, NULL), 0);
    const char *path = BRUME_DATA_DIR "/box_fog_21cube.vdb";
    size_t first = 0;
    for (int k = 0; k < 8; k++) {
        void *buf = NULL;
        size_t n = 0;
        double t0 = test_now();
        if (grid_sandbox_to_nano(path, NULL, 0, path, NULL, 0, (size_t)256 << 20, &buf, &n) != BRUME_OK)
            TEST_FAIL("read %d: %s", k, err_message());
        printf("read %d: %zu bytes of NanoVDB in %.2f s\n", k, n, test_now() - t0);
        ASSERT_TRUE(n >= 64 && ((uintptr_t)buf & 31) == 0);
        if (k == 0)
            first = n;
        ASSERT_TRUE(n == first);
        free(buf);
    }
    atomic_store(&stop, true);
    for (int i = 0; i < 2; i++)
        pthread_join(t[i], NULL);
    ASSERT_EQ_INT(atomic_load(&forks), 0);
}

/* A .vdb given as bytes (no file: brume_density from memory) reaches the child through a
 * memory file: the NanoVDB grid is the file's, byte for byte; the grid list too. */
TEST(vdb_bytes_reach_the_reader_whole)
{
    need_openvdb();
    const char *path = BRUME_DATA_DIR "/box_fog_21cube.vdb";
    size_t size = 0;
    char *bytes = test_slurp(path, &size);
    void *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    if (grid_sandbox_to_nano(path, NULL, 0, "file", NULL, 0, (size_t)256 << 20, &a, &na) != BRUME_OK ||
        grid_sandbox_to_nano(NULL, bytes, size, "bytes", NULL, 0, (size_t)256 << 20, &b, &nb) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    ASSERT_TRUE(na == nb && na > 0);
    ASSERT_TRUE(memcmp(a, b, na) == 0);
    gridvdb_info *in = NULL;
    int count = 0;
    if (grid_sandbox_list(NULL, bytes, size, "bytes", (size_t)256 << 20, &in, &count) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    ASSERT_TRUE(count >= 1);
    printf("%d grid(s), the first \"%s\" (%s)\n", count, in[0].name, in[0].type);
    /* cut short, the bytes are a refusal in one line naming the input, not a hang */
    void *c = NULL;
    size_t nc = 0;
    ASSERT_TRUE(grid_sandbox_to_nano(NULL, bytes, size / 2, "half", NULL, 0, (size_t)256 << 20, &c, &nc) != BRUME_OK);
    ASSERT_CONTAINS(err_message(), "half");
    ASSERT_TRUE(strchr(err_message(), '\n') == NULL);
    free(in);
    free(a);
    free(b);
    free(bytes);
}

/* The program is not a command: run by hand, it says so in one line and exits 2. */
TEST(reader_program_refuses_a_command_line)
{
    need_openvdb();
    const char *err = test_tmp_path("reader.txt");
    char exe[4096], cmd[8400];
    snprintf(exe, sizeof exe, "%s", BRUME_EXE);
    char *slash = strrchr(exe, '/');
    ASSERT_TRUE(slash != NULL);
    snprintf(slash + 1, sizeof exe - (size_t)(slash + 1 - exe), "%s", VDB_PATH_READER_FILE);
    snprintf(cmd, sizeof cmd, "'%s' some.vdb 2>'%s'", exe, err);
    ASSERT_EQ_INT(test_system(cmd), 2);
    size_t n;
    char *text = test_slurp(err, &n);
    ASSERT_CONTAINS(text, "not a command");
    ASSERT_TRUE(strchr(text, '\n') == text + n - 1);
    free(text);
}

TEST_MAIN(vdb_reader_is_a_program_not_a_fork, vdb_bytes_reach_the_reader_whole, reader_program_refuses_a_command_line)
