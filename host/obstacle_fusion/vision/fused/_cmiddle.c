/* The fused vision method's optional C accelerator: the two middle order statistics of
 * every lane of an 8-bit array (profiles.median_u8 takes its medians from them).
 *
 * The colour stages take a median per row, column or channel of small Lab blocks: many
 * short lanes (a few rows of a 500-column band, 6 columns of a 100-row strip), where
 * numpy's sort costs a call per lane and profiles.py's selection network a numpy call per
 * comparator. Here the same network runs over all lanes at once, in one call. Minima and
 * maxima of integers: exactly the values numpy's sort gives. Built by setup.py (optional:
 * without it, profiles.py does the same in numpy). Reads any strided buffer (numpy views).
 * Also profiles.walk_on's walk along a row of flags (a Python loop of a few hundred steps,
 * a dozen walks a frame), profiles.first_gap's search down each column of flags and
 * profiles.next_true's running minimum up them, and search.ramp_columns' gradient walks
 * round the candidate side columns (ramp_spans), profiles.row_norms' norms of colours,
 * View.lab's held-block bookkeeping (uncovered), and scoring.score_pairs' top candidates
 * with their features (score_tops: numpy's float operations in numpy's order), and
 * search._rank_sides' ranking of the side columns (rank_sides: the same, None on a tie)
 * and search.Sides' presence tables (side_tables), and search.line_columns' thin lines
 * (line_columns).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <limits.h>
#include <math.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <string.h>

/* Dimensions a source may have (numpy's own limit is 64). */
#define MAX_DIMS 64

static int is_u8(const Py_buffer *b)
{
    return b->itemsize == 1 && (b->format == NULL || strcmp(b->format, "B") == 0);
}

static int is_i32(const Py_buffer *b)
{
    return b->itemsize == 4 && b->format != NULL &&
           (strcmp(b->format, "i") == 0 || strcmp(b->format, "l") == 0);
}

/* One comparator over all lanes: the minimum to x (when wanted), the maximum to y. */
static void compare(unsigned char *restrict x, unsigned char *restrict y, Py_ssize_t lanes,
                    int want)
{
    if (want == 3) {
        for (Py_ssize_t l = 0; l < lanes; l++) {
            unsigned char a = x[l], b = y[l];
            x[l] = a < b ? a : b;
            y[l] = a < b ? b : a;
        }
    } else if (want == 1) {
        for (Py_ssize_t l = 0; l < lanes; l++)
            x[l] = x[l] < y[l] ? x[l] : y[l];
    } else {
        for (Py_ssize_t l = 0; l < lanes; l++)
            y[l] = x[l] < y[l] ? y[l] : x[l];
    }
}

/* The count of values v..v+15 in the two tables of middles_by_count (whose 16-bit
 * entries over both tables add up to at most 65535: no 16-bit sum of them wraps). */
static Py_ssize_t block_count(const unsigned short count[2][256], int v)
{
#ifdef __SSE2__
    __m128i s = _mm_add_epi16(
        _mm_add_epi16(_mm_loadu_si128((const __m128i *)&count[0][v]),
                      _mm_loadu_si128((const __m128i *)&count[1][v])),
        _mm_add_epi16(_mm_loadu_si128((const __m128i *)&count[0][v + 8]),
                      _mm_loadu_si128((const __m128i *)&count[1][v + 8])));
    /* eight 16-bit sums to four 32-bit ones (unsigned: the high halves masked), then two,
     * then one */
    __m128i lo16 = _mm_and_si128(s, _mm_set1_epi32(0xffff));
    __m128i t = _mm_add_epi32(lo16, _mm_srli_epi32(s, 16));
    t = _mm_add_epi32(t, _mm_shuffle_epi32(t, _MM_SHUFFLE(1, 0, 3, 2)));
    t = _mm_add_epi32(t, _mm_shuffle_epi32(t, _MM_SHUFFLE(2, 3, 0, 1)));
    return (Py_ssize_t)_mm_cvtsi128_si32(t);
#else
    Py_ssize_t block = 0;
    for (int j = 0; j < 16; j++)
        block += count[0][v + j] + count[1][v + j];
    return block;
#endif
}

/* The values at sorted positions k - 1 and k (1 <= k < n) of a lane of n bytes ``step``
 * apart, read off counts of its values: one pass over the lane, one over the counts up to
 * the k-th. Counts in 16 bits for lanes of up to 65535 values (a 512-byte table to clear),
 * else in Py_ssize_t. Exact, as a sort's. */
static void middles_by_count(const char *from, Py_ssize_t step, Py_ssize_t n, Py_ssize_t k,
                             unsigned char *lo, unsigned char *hi)
{
    int v = 0, first = -1;
    if (n <= 65535) {
        /* two tables, alternate values: runs of one value (a lane of one colour) do not
         * wait on their own increments */
        unsigned short count[2][256];
        memset(count, 0, sizeof count);
        Py_ssize_t i = 0;
        for (; i + 1 < n; i += 2) {
            count[0][(unsigned char)from[i * step]]++;
            count[1][(unsigned char)from[(i + 1) * step]]++;
        }
        if (i < n)
            count[0][(unsigned char)from[i * step]]++;
        /* the 16-value block holding the (k-1)-th, then value by value from there */
        Py_ssize_t below = 0;
        for (; v < 240; v += 16) {
            Py_ssize_t block = block_count(count, v);
            if (below + block > k - 1)
                break;
            below += block;
        }
        for (; v < 256; v++) {
            below += count[0][v] + count[1][v];
            if (first < 0 && below > k - 1)
                first = v;
            if (below > k)
                break;
        }
    } else {
        Py_ssize_t count[256];
        memset(count, 0, sizeof count);
        for (Py_ssize_t i = 0; i < n; i++)
            count[(unsigned char)from[i * step]]++;
        Py_ssize_t below = 0;
        for (; v < 256; v++) {
            below += count[v];
            if (first < 0 && below > k - 1)
                first = v;
            if (below > k)
                break;
        }
    }
    *lo = (unsigned char)first;
    *hi = (unsigned char)v;
}

/* The two middles of every lane of src along its axis ``axis`` (n = src.shape[axis]
 * values, any strides), lanes in C order of src's other axes, by the comparator network
 * ``net`` (net_len bytes, checked by the caller) or, for an empty one, by counts: into lo
 * and hi (one byte per lane each) when ``mid`` is NULL, else into mid their float32 median
 * (hi for an odd n, (lo + hi) / 2 for an even one: 8-bit values and their half sums are
 * exact in float32, numpy's float median of the lane). 0, or -1 with an error set. */
static int middles(const Py_buffer *src, int axis, const unsigned char *net, Py_ssize_t net_len,
                   unsigned char *lo, unsigned char *hi, float *mid)
{
    int nd = src->ndim;
    Py_ssize_t n = src->shape[axis], lanes = 1;
    for (int d = 0; d < nd; d++)
        lanes *= d == axis ? 1 : src->shape[d];
    if (lanes == 0)
        return 0;
    unsigned char *rows = net_len ? PyMem_Malloc((size_t)(n * lanes)) : NULL;
    Py_ssize_t *offsets = PyMem_Malloc((size_t)lanes * sizeof *offsets);
    if ((net_len && rows == NULL) || offsets == NULL) {
        PyMem_Free(offsets);
        PyMem_Free(rows);
        PyErr_NoMemory();
        return -1;
    }
    /* each lane's first value: an odometer over the other axes, last fastest (lanes next
     * to each other in memory, as a row of values, are copied a row at a time) */
    /* (the innermost of the other axes in a plain loop, with the axes outside it that
     * continue it evenly (a row of pixels' channels and columns: one run), the odometer
     * over the rest: one step of it per run of lanes) */
    Py_ssize_t index[MAX_DIMS] = {0}, at = 0;
    int inner = nd - 1 == axis ? nd - 2 : nd - 1;
    Py_ssize_t run = inner >= 0 ? src->shape[inner] : 1;
    Py_ssize_t run_step = inner >= 0 ? src->strides[inner] : 0;
    int outer = inner; /* the odometer's axes: those before it */
    for (int d = inner - 1; d >= 0; d--) {
        if (d == axis)
            continue;
        if (src->strides[d] != run_step * run)
            break;
        run *= src->shape[d];
        outer = d;
    }
    int adjacent = 1;
    for (Py_ssize_t lane = 0; lane < lanes; lane += run) {
        for (Py_ssize_t j = 0; j < run; j++)
            offsets[lane + j] = at + j * run_step;
        adjacent &= at == lane && (run == 1 || run_step == 1);
        for (int d = outer - 1; d >= 0; d--) {
            if (d == axis)
                continue;
            at += src->strides[d];
            if (++index[d] < src->shape[d])
                break;
            at -= src->strides[d] * src->shape[d];
            index[d] = 0;
        }
    }
    const char *base = (const char *)src->buf;
    Py_ssize_t step = src->strides[axis];
    Py_ssize_t k = n / 2;
    int odd = (int)(n % 2);
    if (net_len == 0) {
        /* no network: each lane's middles read off counts of its values (long lanes,
         * where a network would be long and numpy sorts a 16-bit copy; a selection in a
         * copy of the lane mispredicts a branch per value, ~9x the counts' time) */
        for (Py_ssize_t lane = 0; lane < lanes; lane++) {
            unsigned char l, h;
            middles_by_count(base + offsets[lane], step, n, k, &l, &h);
            if (mid != NULL) {
                mid[lane] = odd ? (float)h : ((float)l + (float)h) / 2.0f;
            } else {
                lo[lane] = l;
                hi[lane] = h;
            }
        }
        PyMem_Free(offsets);
        return 0;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        unsigned char *row = rows + i * lanes;
        const char *from = base + i * step;
        if (adjacent) {
            memcpy(row, from, (size_t)lanes);
            continue;
        }
        for (Py_ssize_t lane = 0; lane < lanes; lane++)
            row[lane] = (unsigned char)from[offsets[lane]];
    }
    for (Py_ssize_t c = 0; c < net_len; c += 3)
        compare(rows + net[c] * lanes, rows + net[c + 1] * lanes, lanes, net[c + 2]);
    const unsigned char *low = rows + (k - 1) * lanes, *high = rows + k * lanes;
    if (mid == NULL) {
        memcpy(lo, low, (size_t)lanes);
        memcpy(hi, high, (size_t)lanes);
    } else if (odd) {
        for (Py_ssize_t lane = 0; lane < lanes; lane++)
            mid[lane] = (float)high[lane];
    } else {
        for (Py_ssize_t lane = 0; lane < lanes; lane++)
            mid[lane] = ((float)low[lane] + (float)high[lane]) / 2.0f;
    }
    PyMem_Free(offsets);
    PyMem_Free(rows);
    return 0;
}

/* The network's checks: whole comparators inside lanes of n values. 0, or -1 with an
 * error set. */
static int check_network(const unsigned char *net, Py_ssize_t net_len, Py_ssize_t n,
                         const char *name)
{
    if (net_len % 3 != 0) {
        PyErr_Format(PyExc_ValueError, "%s: lanes of at least two values", name);
        return -1;
    }
    for (Py_ssize_t c = 0; c < net_len; c += 3) {
        if (net[c] >= n || net[c + 1] >= n || net[c] == net[c + 1] || net[c + 2] > 3) {
            PyErr_Format(PyExc_ValueError, "%s: a comparator outside the lanes", name);
            return -1;
        }
    }
    return 0;
}

/* middle_u8(src, network, lo, hi): for every lane along src's last axis (uint8, any
 * strides, n values), the sorted values at n // 2 - 1 and n // 2 into lo and hi (C-contiguous
 * uint8, one entry per lane in C order of src's other axes), by the comparator network
 * given as bytes (i, j, want) per comparator: the minimum of values i and j to i (want
 * bit 0), their maximum to j (bit 1); the caller's network leaves the middles at n // 2 - 1
 * and n // 2. The lanes are gathered into n rows of all lanes, so that each comparator is
 * one pass of byte minima and maxima over contiguous rows. An empty network: each lane's
 * middles are read off counts of its values (any length). */
static PyObject *middle_u8(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *src_obj, *lo_obj, *hi_obj;
    const unsigned char *net;
    Py_ssize_t net_len;
    if (!PyArg_ParseTuple(args, "Oy#OO:middle_u8", &src_obj, &net, &net_len, &lo_obj, &hi_obj))
        return NULL;
    Py_buffer src, lo, hi;
    if (PyObject_GetBuffer(src_obj, &src, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(lo_obj, &lo, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0) {
        PyBuffer_Release(&src);
        return NULL;
    }
    if (PyObject_GetBuffer(hi_obj, &hi, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0) {
        PyBuffer_Release(&lo);
        PyBuffer_Release(&src);
        return NULL;
    }
    PyObject *result = NULL;
    int nd = src.ndim;
    if (!is_u8(&src) || !is_u8(&lo) || !is_u8(&hi)) {
        PyErr_SetString(PyExc_TypeError, "middle_u8: uint8 arrays only");
        goto done;
    }
    if (nd < 1 || nd > MAX_DIMS || src.shape[nd - 1] < 2 || net_len % 3 != 0) {
        PyErr_SetString(PyExc_ValueError, "middle_u8: lanes of at least two values");
        goto done;
    }
    Py_ssize_t lanes = 1;
    for (int d = 0; d < nd - 1; d++)
        lanes *= src.shape[d];
    if (lo.len != lanes || hi.len != lanes) {
        PyErr_SetString(PyExc_ValueError, "middle_u8: one output entry per lane");
        goto done;
    }
    if (check_network(net, net_len, src.shape[nd - 1], "middle_u8") < 0)
        goto done;
    if (middles(&src, nd - 1, net, net_len, lo.buf, hi.buf, NULL) < 0)
        goto done;
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyBuffer_Release(&hi);
    PyBuffer_Release(&lo);
    PyBuffer_Release(&src);
    return result;
}

/* median_f32(src, axis, network, out): the float32 median of every lane of src (uint8,
 * any strides, n >= 2 values) along ``axis`` into out (C-contiguous float32, one entry per
 * lane in C order of src's other axes): middle_u8's middles (the same network, or an
 * empty one: counts), the upper one for an odd n, the two averaged in float32 for an even
 * one; numpy's float32 median of the lane (profiles.median_u8 without its numpy steps). */
static PyObject *median_f32(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *src_obj, *out_obj;
    int axis;
    const unsigned char *net;
    Py_ssize_t net_len;
    if (!PyArg_ParseTuple(args, "Oiy#O:median_f32", &src_obj, &axis, &net, &net_len, &out_obj))
        return NULL;
    Py_buffer src, out;
    if (PyObject_GetBuffer(src_obj, &src, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) <
        0) {
        PyBuffer_Release(&src);
        return NULL;
    }
    PyObject *result = NULL;
    int nd = src.ndim;
    if (!is_u8(&src) || out.itemsize != 4 || out.format == NULL || strcmp(out.format, "f") != 0) {
        PyErr_SetString(PyExc_TypeError, "median_f32: uint8 source, float32 output");
        goto done;
    }
    if (nd < 1 || nd > MAX_DIMS || axis < 0 || axis >= nd || src.shape[axis] < 2) {
        PyErr_SetString(PyExc_ValueError, "median_f32: lanes of at least two values");
        goto done;
    }
    Py_ssize_t lanes = 1;
    for (int d = 0; d < nd; d++)
        lanes *= d == axis ? 1 : src.shape[d];
    if (out.len != lanes * 4) {
        PyErr_SetString(PyExc_ValueError, "median_f32: one output entry per lane");
        goto done;
    }
    if (check_network(net, net_len, src.shape[axis], "median_f32") < 0)
        goto done;
    if (middles(&src, axis, net, net_len, NULL, NULL, (float *)out.buf) < 0)
        goto done;
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyBuffer_Release(&out);
    PyBuffer_Release(&src);
    return result;
}

/* walk_on(on, start, step, max_gap): profiles.walk_on's walk, for a list (or any
 * sequence) of flags, or a 1-D bool or uint8 array read in place: from ``start`` towards
 * ``step``, the last true index reached over runs of at most ``max_gap`` false ones.
 * Returns None for a step of 0 or indices near the integer limits (the caller walks in
 * Python then). */
static int flag_at(PyObject **items, const Py_buffer *view, Py_ssize_t i)
{
    if (items != NULL)
        return PyObject_IsTrue(items[i]);
    return ((const unsigned char *)view->buf)[i * view->strides[0]] != 0;
}

static PyObject *walk_on(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *on;
    Py_ssize_t start, step, max_gap;
    if (!PyArg_ParseTuple(args, "Onnn:walk_on", &on, &start, &step, &max_gap))
        return NULL;
    const Py_ssize_t limit = PY_SSIZE_T_MAX / 4;
    if (step == 0 || step > limit || step < -limit || start > limit || start < -limit)
        Py_RETURN_NONE;
    Py_buffer view;
    PyObject *seq = NULL, **items = NULL;
    int buffered = 0;
    Py_ssize_t n;
    if (PyObject_CheckBuffer(on) && !PyBytes_Check(on) && !PyByteArray_Check(on) &&
        PyObject_GetBuffer(on, &view, PyBUF_STRIDES | PyBUF_FORMAT) == 0) {
        if (view.ndim == 1 && view.itemsize == 1 && view.format != NULL &&
            (strcmp(view.format, "?") == 0 || strcmp(view.format, "B") == 0)) {
            buffered = 1;
            n = view.shape[0];
        } else {
            PyBuffer_Release(&view);
        }
    } else {
        PyErr_Clear();
    }
    if (!buffered) {
        seq = PySequence_Fast(on, "walk_on: flags must be a sequence");
        if (seq == NULL)
            return NULL;
        items = PySequence_Fast_ITEMS(seq);
        n = PySequence_Fast_GET_SIZE(seq);
    }
    Py_ssize_t u = start, v = start, gap = 0;
    int failed = 0;
    while (0 <= v + step && v + step < n && gap <= max_gap) {
        v += step;
        int flag = flag_at(items, buffered ? &view : NULL, v);
        if (flag < 0) {
            failed = 1;
            break;
        }
        if (flag) {
            u = v;
            gap = 0;
        } else {
            gap++;
        }
    }
    if (buffered)
        PyBuffer_Release(&view);
    Py_XDECREF(seq);
    return failed ? NULL : PyLong_FromSsize_t(u);
}

/* first_gap(on, out): profiles.first_gap for a 2-D bool array (any strides): per column,
 * the first row starting 3 consecutive false ones (with fewer than 3 rows, the first
 * false one), the row count if none, into out (C-contiguous, one 8-byte integer per
 * column). */
static PyObject *first_gap(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *on_obj, *out_obj;
    if (!PyArg_ParseTuple(args, "OO:first_gap", &on_obj, &out_obj))
        return NULL;
    Py_buffer on, out;
    if (PyObject_GetBuffer(on_obj, &on, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0) {
        PyBuffer_Release(&on);
        return NULL;
    }
    PyObject *result = NULL;
    if (on.ndim != 2 || on.itemsize != 1 || on.format == NULL || strcmp(on.format, "?") != 0 ||
        out.itemsize != (Py_ssize_t)sizeof(long long) || out.len != on.shape[1] * out.itemsize) {
        PyErr_SetString(PyExc_TypeError, "first_gap: a 2-D bool array and one int64 per column");
        goto done;
    }
    Py_ssize_t rows = on.shape[0], cols = on.shape[1];
    Py_ssize_t rs = on.strides[0], cs = on.strides[1];
    const char *base = (const char *)on.buf;
    long long *found = (long long *)out.buf;
    for (Py_ssize_t c = 0; c < cols; c++) {
        const char *col = base + c * cs;
        Py_ssize_t at = rows;
        if (rows > 2) {
            for (Py_ssize_t r = 0; r + 2 < rows; r++) {
                if (!col[r * rs] && !col[(r + 1) * rs] && !col[(r + 2) * rs]) {
                    at = r;
                    break;
                }
            }
        } else {
            for (Py_ssize_t r = 0; r < rows; r++) {
                if (!col[r * rs]) {
                    at = r;
                    break;
                }
            }
        }
        found[c] = (long long)at;
    }
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyBuffer_Release(&out);
    PyBuffer_Release(&on);
    return result;
}

/* next_true(flags, fill, out): profiles.next_true for a 2-D bool array (any strides):
 * out[r, c] = the minimum over rows r' >= r of (r' where flags[r', c], else fill), into
 * out (C-contiguous, one 8-byte integer per entry). */
static PyObject *next_true(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *flags_obj, *out_obj;
    long long fill;
    if (!PyArg_ParseTuple(args, "OLO:next_true", &flags_obj, &fill, &out_obj))
        return NULL;
    Py_buffer flags, out;
    if (PyObject_GetBuffer(flags_obj, &flags, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0) {
        PyBuffer_Release(&flags);
        return NULL;
    }
    PyObject *result = NULL;
    if (flags.ndim != 2 || flags.itemsize != 1 || flags.format == NULL ||
        strcmp(flags.format, "?") != 0 || out.itemsize != (Py_ssize_t)sizeof(long long) ||
        out.len != flags.shape[0] * flags.shape[1] * out.itemsize) {
        PyErr_SetString(PyExc_TypeError, "next_true: a 2-D bool array and one int64 per entry");
        goto done;
    }
    Py_ssize_t rows = flags.shape[0], cols = flags.shape[1];
    Py_ssize_t rs = flags.strides[0], cs = flags.strides[1];
    const char *base = (const char *)flags.buf;
    long long *to = (long long *)out.buf;
    for (Py_ssize_t c = 0; c < cols; c++) {
        long long low = LLONG_MAX;
        for (Py_ssize_t r = rows - 1; r >= 0; r--) {
            long long here = base[r * rs + c * cs] ? (long long)r : fill;
            if (here < low)
                low = here;
            to[r * cols + c] = low;
        }
    }
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyBuffer_Release(&out);
    PyBuffer_Release(&flags);
    return result;
}



/* The table remaps' five buffers (source, offsets, two weight tables, destination), in that
 * order: the count acquired; 5 unless one failed (its error set), the rest released by
 * release_buffers(views, count). */
static int table_buffers(PyObject *objs[5], Py_buffer *views[5])
{
    static const int flags[5] = {
        PyBUF_STRIDES | PyBUF_FORMAT, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT,
        PyBUF_C_CONTIGUOUS | PyBUF_FORMAT, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT,
        PyBUF_STRIDES | PyBUF_FORMAT | PyBUF_WRITABLE};
    int got = 0;
    for (; got < 5; got++) {
        if (PyObject_GetBuffer(objs[got], views[got], flags[got]) < 0)
            break;
    }
    return got;
}

static void release_buffers(Py_buffer *views[], int count)
{
    for (int i = count - 1; i >= 0; i--)
        PyBuffer_Release(views[i]);
}

/* remap_table(src, stride, offsets, fx, fy, dst): OpenCV's bilinear remap of a grey 8-bit
 * image (INTER_LINEAR, BORDER_REPLICATE, fixed-point maps) from a table made once per view
 * (undistort.remap_table): per output pixel the offset of its top-left source pixel in src
 * (rows ``stride`` bytes apart) and its weights fx, fy in 32nds (0..32). OpenCV weighs
 * the four pixels (32 - fy)(32 - fx) x 32 ... in 15 bits and rounds (sum + 2**14) >> 15;
 * every weight is a multiple of 32, so that is (sum / 32 + 2**9) >> 10: the same integer.
 * A pixel that reads past the image's border reads the nearest border pixel twice; the
 * table says the same with fx or fy 0 (or 32, one pixel in) and the pair inside the image.
 * The table's offsets are checked against src. Returns None. Integer arithmetic: the
 * values are OpenCV's bit for bit; OpenCV's own loop costs ~39 instructions a pixel here,
 * this one (8 pixels at a time in SSE2 where there is SSE2) ~19. */
static PyObject *remap_table(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *src_obj, *off_obj, *fx_obj, *fy_obj, *dst_obj;
    Py_ssize_t stride;
    if (!PyArg_ParseTuple(args, "OnOOOO:remap_table", &src_obj, &stride, &off_obj, &fx_obj,
                          &fy_obj, &dst_obj))
        return NULL;
    Py_buffer src, off, fx, fy, dst;
    Py_buffer *views[5] = {&src, &off, &fx, &fy, &dst};
    PyObject *objs[5] = {src_obj, off_obj, fx_obj, fy_obj, dst_obj};
    int got = table_buffers(objs, views);
    PyObject *result = NULL;
    if (got < 5)
        goto done;
    if (!is_u8(&src) || !is_u8(&dst) || off.itemsize != 4 || off.format == NULL ||
        (strcmp(off.format, "i") != 0 && strcmp(off.format, "l") != 0) || fx.itemsize != 2 ||
        fy.itemsize != 2 || fx.format == NULL || fy.format == NULL ||
        strcmp(fx.format, "h") != 0 || strcmp(fy.format, "h") != 0 || src.ndim != 2 ||
        dst.ndim != 2 || off.ndim != 2 || fx.ndim != 2 || fy.ndim != 2) {
        PyErr_SetString(PyExc_TypeError,
                        "remap_table: 2-D uint8 images, int32 offsets, int16 weights");
        goto done;
    }
    Py_ssize_t n = dst.shape[0], m = dst.shape[1];
    if (off.shape[0] < n || off.shape[1] != m || fx.shape[0] != off.shape[0] ||
        fx.shape[1] != m || fy.shape[0] != off.shape[0] || fy.shape[1] != m ||
        src.strides[0] != stride || src.strides[1] != 1 || dst.strides[1] != 1 ||
        src.shape[0] < 2 || src.shape[1] < 2 || stride < src.shape[1]) {
        PyErr_SetString(PyExc_ValueError, "remap_table: a table for this image and output");
        goto done;
    }
    /* the last offset a pair of rows may start at: both pixels of both rows inside the
     * buffer (every offset is checked before it is read, and every weight: one outside
     * 0..32 is refused, as an offset past this one) */
    long long last = (long long)(src.shape[0] - 2) * stride + src.shape[1] - 2;
    if (last > INT_MAX) {
        PyErr_SetString(PyExc_ValueError, "remap_table: an image too large for the table");
        goto done;
    }
    const unsigned limit = (unsigned)last;
    const unsigned char *base = (const unsigned char *)src.buf;
    const int *offs = (const int *)off.buf;
    const short *wx = (const short *)fx.buf, *wy = (const short *)fy.buf;
    for (Py_ssize_t r = 0; r < n; r++) {
        const int *o = offs + r * m;
        const short *ax = wx + r * m, *ay = wy + r * m;
        unsigned char *out = (unsigned char *)dst.buf + r * dst.strides[0];
        Py_ssize_t c = 0;
#ifdef __SSE2__
        const __m128i zero = _mm_setzero_si128(), k32 = _mm_set1_epi16(32),
                      half = _mm_set1_epi32(512);
        for (; c + 8 <= m; c += 8) {
            unsigned short t[8], b[8]; /* the pixel pairs of the top and bottom rows */
            for (int k = 0; k < 8; k++) {
                unsigned at = (unsigned)o[c + k];
                if (at > limit)
                    goto outside;
                memcpy(&t[k], base + at, 2); /* little-endian: first pixel low */
                memcpy(&b[k], base + at + stride, 2);
            }
            __m128i top = _mm_loadu_si128((const __m128i *)(const void *)t);
            __m128i bot = _mm_loadu_si128((const __m128i *)(const void *)b);
            __m128i fx8 = _mm_loadu_si128((const __m128i *)(const void *)(ax + c));
            __m128i fy8 = _mm_loadu_si128((const __m128i *)(const void *)(ay + c));
            __m128i wbad = _mm_or_si128(_mm_cmpgt_epi16(_mm_max_epi16(fx8, fy8), k32),
                                        _mm_cmplt_epi16(_mm_min_epi16(fx8, fy8), zero));
            if (_mm_movemask_epi8(wbad))
                goto outside;
            /* weight pairs (32 - f, f) per pixel, in the order of the byte pairs */
            __m128i gx = _mm_sub_epi16(k32, fx8), gy = _mm_sub_epi16(k32, fy8);
            __m128i wx_lo = _mm_unpacklo_epi16(gx, fx8), wx_hi = _mm_unpackhi_epi16(gx, fx8);
            __m128i wy_lo = _mm_unpacklo_epi16(gy, fy8), wy_hi = _mm_unpackhi_epi16(gy, fy8);
            /* along the rows: v0 (32 - fx) + v1 fx, <= 8160 */
            __m128i t_lo = _mm_madd_epi16(_mm_unpacklo_epi8(top, zero), wx_lo);
            __m128i t_hi = _mm_madd_epi16(_mm_unpackhi_epi8(top, zero), wx_hi);
            __m128i b_lo = _mm_madd_epi16(_mm_unpacklo_epi8(bot, zero), wx_lo);
            __m128i b_hi = _mm_madd_epi16(_mm_unpackhi_epi8(bot, zero), wx_hi);
            __m128i tt = _mm_packs_epi32(t_lo, t_hi), bb = _mm_packs_epi32(b_lo, b_hi);
            /* across: top (32 - fy) + bottom fy, rounded */
            __m128i v_lo = _mm_madd_epi16(_mm_unpacklo_epi16(tt, bb), wy_lo);
            __m128i v_hi = _mm_madd_epi16(_mm_unpackhi_epi16(tt, bb), wy_hi);
            v_lo = _mm_srai_epi32(_mm_add_epi32(v_lo, half), 10);
            v_hi = _mm_srai_epi32(_mm_add_epi32(v_hi, half), 10);
            __m128i v = _mm_packs_epi32(v_lo, v_hi);
            _mm_storel_epi64((__m128i *)(void *)(out + c), _mm_packus_epi16(v, v));
        }
#endif
        for (; c < m; c++) {
            unsigned at = (unsigned)o[c];
            int gx = ax[c], gy = ay[c];
            if (at > limit || (unsigned)gx > 32u || (unsigned)gy > 32u)
                goto outside;
            const unsigned char *p = base + at;
            int top = p[0] * (32 - gx) + p[1] * gx;
            int bottom = p[stride] * (32 - gx) + p[stride + 1] * gx;
            out[c] = (unsigned char)((top * (32 - gy) + bottom * gy + 512) >> 10);
        }
    }
    Py_INCREF(Py_None);
    result = Py_None;
    goto done;
outside:
    PyErr_SetString(PyExc_ValueError,
                    "remap_table: an entry outside the image, or a weight outside 0..32");
done:
    release_buffers(views, got);
    return result;
}


/* remap_table3(src, offsets, wtop, wbot, r0, c0, dst): remap_table's remap of a packed
 * BGR image (rows 3 x its width bytes apart: a BGR pixel's byte offset is three times the
 * grey one the table holds for the same width), each channel as OpenCV remaps it (its
 * bilinear weights are per pixel, the same for every channel), for the view block whose
 * top-left pixel is (r0, c0) in the full-view table: dst (rows, columns, 3). wtop and wbot
 * hold per pixel the products of remap_table's weights, in 16-bit halves: (32 - fx)(32 - fy)
 * and fx (32 - fy) for the top row's two pixels, (32 - fx) fy and fx fy for the bottom's;
 * the sum of the four weighed pixels, + 2**9, >> 10 is remap_table's integer. The colour
 * stages convert a few dozen small view blocks a frame to Lab: OpenCV's remap takes ~55
 * instructions a BGR pixel here and a call's overhead on top. Only the offsets are checked
 * (memory safety); weights outside 0..1024 give wrong values, never a wrong access. */
static PyObject *remap_table3(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *src_obj, *off_obj, *wt_obj, *wb_obj, *dst_obj;
    Py_ssize_t r0, c0;
    if (!PyArg_ParseTuple(args, "OOOOnnO:remap_table3", &src_obj, &off_obj, &wt_obj, &wb_obj,
                          &r0, &c0, &dst_obj))
        return NULL;
    Py_buffer src, off, wt, wb, dst;
    Py_buffer *views[5] = {&src, &off, &wt, &wb, &dst};
    PyObject *objs[5] = {src_obj, off_obj, wt_obj, wb_obj, dst_obj};
    int got = table_buffers(objs, views);
    PyObject *result = NULL;
    if (got < 5)
        goto done;
    if (!is_u8(&src) || !is_u8(&dst) || !is_i32(&off) || !is_i32(&wt) || !is_i32(&wb) ||
        src.ndim != 3 || dst.ndim != 3 || off.ndim != 2 || wt.ndim != 2 || wb.ndim != 2) {
        PyErr_SetString(PyExc_TypeError,
                        "remap_table3: 3-D uint8 images, int32 offsets and weights");
        goto done;
    }
    Py_ssize_t n = dst.shape[0], m = dst.shape[1], w = src.shape[1];
    Py_ssize_t stride = src.strides[0];
    if (src.shape[2] != 3 || dst.shape[2] != 3 || src.strides[2] != 1 || src.strides[1] != 3 ||
        stride != 3 * w || dst.strides[2] != 1 || dst.strides[1] != 3 || src.shape[0] < 2 ||
        w < 3 || r0 < 0 || c0 < 0 || wt.shape[0] != off.shape[0] ||
        wt.shape[1] != off.shape[1] || wb.shape[0] != off.shape[0] ||
        wb.shape[1] != off.shape[1] || r0 + n > off.shape[0] || c0 + m > off.shape[1]) {
        PyErr_SetString(PyExc_ValueError, "remap_table3: a table for this image and block");
        goto done;
    }
    /* the last grey offset a pair of rows may start at (as in remap_table) */
    long long last = (long long)(src.shape[0] - 2) * w + w - 2;
    if (3 * last + stride + 8 > (long long)INT_MAX) {
        PyErr_SetString(PyExc_ValueError, "remap_table3: an image too large for the table");
        goto done;
    }
    const unsigned limit = (unsigned)last;
    /* up to this grey offset 8 bytes may be read at both rows (the bottom row's run off
     * the image's last row past it) */
    const unsigned wide_limit = (unsigned)(last - 1);
    const unsigned char *base = (const unsigned char *)src.buf;
    const Py_ssize_t tw = off.shape[1];
    for (Py_ssize_t r = 0; r < n; r++) {
        const int *restrict o = (const int *)off.buf + (r0 + r) * tw + c0;
        const int *restrict at_top = (const int *)wt.buf + (r0 + r) * tw + c0;
        const int *restrict at_bot = (const int *)wb.buf + (r0 + r) * tw + c0;
        unsigned char *restrict out = (unsigned char *)dst.buf + r * dst.strides[0];
        for (Py_ssize_t c = 0; c < m; c++) {
            unsigned at = (unsigned)o[c];
            if (at > limit)
                goto outside;
            const unsigned char *p = base + 3 * (size_t)at;
#ifdef __SSE2__
            const __m128i zero = _mm_setzero_si128();
            __m128i top, bot;
            if (at <= wide_limit) {
                top = _mm_loadl_epi64((const __m128i *)(const void *)p);
                bot = _mm_loadl_epi64((const __m128i *)(const void *)(p + stride));
            } else {
                long long t = 0, b = 0;
                memcpy(&t, p, 6);
                memcpy(&b, p + stride, 6);
                top = _mm_cvtsi64_si128(t);
                bot = _mm_cvtsi64_si128(b);
            }
            top = _mm_unpacklo_epi8(top, zero); /* the two pixels' channels, 16 bits */
            bot = _mm_unpacklo_epi8(bot, zero);
            /* (first, second) pixel's value per channel, by their weights */
            __m128i v = _mm_add_epi32(
                _mm_madd_epi16(_mm_unpacklo_epi16(top, _mm_srli_si128(top, 6)),
                               _mm_shuffle_epi32(_mm_cvtsi32_si128(at_top[c]), 0)),
                _mm_madd_epi16(_mm_unpacklo_epi16(bot, _mm_srli_si128(bot, 6)),
                               _mm_shuffle_epi32(_mm_cvtsi32_si128(at_bot[c]), 0)));
            v = _mm_srai_epi32(_mm_add_epi32(v, _mm_set1_epi32(512)), 10);
            v = _mm_packs_epi32(v, v);
            int bytes = _mm_cvtsi128_si32(_mm_packus_epi16(v, v));
            if (c + 1 < m) {
                memcpy(out + 3 * c, &bytes, 4); /* the 4th byte: the next pixel's, written next */
            } else {
                out[3 * c] = (unsigned char)(bytes & 0xff);
                out[3 * c + 1] = (unsigned char)((bytes >> 8) & 0xff);
                out[3 * c + 2] = (unsigned char)((bytes >> 16) & 0xff);
            }
#else
            unsigned wtop = (unsigned)at_top[c], wbot = (unsigned)at_bot[c];
            int w00 = (short)(wtop & 0xffff), w01 = (short)(wtop >> 16);
            int w10 = (short)(wbot & 0xffff), w11 = (short)(wbot >> 16);
            for (int k = 0; k < 3; k++) {
                int sum = p[k] * w00 + p[k + 3] * w01 + p[stride + k] * w10 +
                          p[stride + k + 3] * w11;
                out[3 * c + k] = (unsigned char)((sum + 512) >> 10);
            }
#endif
        }
    }
    Py_INCREF(Py_None);
    result = Py_None;
    goto done;
outside:
    PyErr_SetString(PyExc_ValueError, "remap_table3: an entry outside the image");
done:
    release_buffers(views, got);
    return result;
}

/* Twice the median over the rows of strip[r, x + 1] - strip[r, x - 1] (1 <= x <= w - 2):
 * the middle value doubled for an odd count, the sum of the two middle ones for an even
 * one; np.median's float64 value of the int16 differences times two, always an integer
 * (search.ramp_columns reads it as float32: multiples of 0.5 under 256, exact). Short
 * lanes by insertion sort on the stack, longer ones by counting the 511 possible
 * differences; both exact. */
#define RAMP_SORT_MAX 64
static long ramp_twice_median(const char *base, Py_ssize_t rows, Py_ssize_t rs, Py_ssize_t cs,
                              Py_ssize_t x)
{
    const char *right = base + (x + 1) * cs, *left = base + (x - 1) * cs;
    Py_ssize_t k = rows / 2;
    if (rows <= RAMP_SORT_MAX) {
        int v[RAMP_SORT_MAX];
        for (Py_ssize_t r = 0; r < rows; r++) {
            int d = (int)((const unsigned char *)right)[r * rs] -
                    (int)((const unsigned char *)left)[r * rs];
            Py_ssize_t i = r;
            while (i > 0 && v[i - 1] > d) {
                v[i] = v[i - 1];
                i--;
            }
            v[i] = d;
        }
        return rows % 2 ? 2L * v[k] : (long)v[k - 1] + v[k];
    }
    Py_ssize_t count[511];
    memset(count, 0, sizeof count);
    for (Py_ssize_t r = 0; r < rows; r++)
        count[255 + (int)((const unsigned char *)right)[r * rs] -
              (int)((const unsigned char *)left)[r * rs]]++;
    /* the values at sorted positions k - 1 and k */
    Py_ssize_t seen = 0;
    int lo = -256, hi = -256;
    for (int d = 0; d < 511; d++) {
        seen += count[d];
        if (lo < -255 && seen > k - 1)
            lo = d - 255;
        if (seen > k) {
            hi = d - 255;
            break;
        }
    }
    return rows % 2 ? 2L * hi : (long)lo + hi;
}

/* ramp_spans(strip, cols, min_cols, beside): search.ramp_columns' walk for each column of
 * ``cols`` over a 2-D uint8 strip (n >= 1 rows, any strides): the column's gradient g
 * (each column's median of the differences across it, 0 at both ends), its peak within
 * one column (the first of the largest |g|), the run of columns either side holding half
 * of it with its sign; a list of (column, first, last) for each column whose run is
 * ``min_cols`` wide or more with ``beside`` columns left beyond both ends, in the order of
 * ``cols`` (duplicates kept). Columns outside 0..w-1: ValueError (the caller walks those
 * in numpy). Gradients are taken only where read, each once (doubled, as integers:
 * comparisons exact; the numpy path takes all w medians of a few rows, a dozen calls). */
static PyObject *ramp_spans(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *strip_obj, *cols_obj;
    Py_ssize_t min_cols, beside;
    if (!PyArg_ParseTuple(args, "OOnn:ramp_spans", &strip_obj, &cols_obj, &min_cols, &beside))
        return NULL;
    PyObject *cols = PySequence_Fast(cols_obj, "ramp_spans: cols must be a sequence");
    if (cols == NULL)
        return NULL;
    Py_buffer strip;
    if (PyObject_GetBuffer(strip_obj, &strip, PyBUF_STRIDES | PyBUF_FORMAT) < 0) {
        Py_DECREF(cols);
        return NULL;
    }
    PyObject *result = NULL;
    long *grad = NULL;      /* twice g per column, where known */
    unsigned char *known = NULL;
    if (strip.ndim != 2 || !is_u8(&strip) || strip.shape[0] < 1) {
        PyErr_SetString(PyExc_TypeError, "ramp_spans: a 2-D uint8 strip of one row or more");
        goto done;
    }
    const Py_ssize_t rows = strip.shape[0], w = strip.shape[1];
    const Py_ssize_t rs = strip.strides[0], cs = strip.strides[1];
    const char *base = (const char *)strip.buf;
    const Py_ssize_t n_cols = PySequence_Fast_GET_SIZE(cols);
    PyObject **items = PySequence_Fast_ITEMS(cols);
    /* one allocation a call (w entries each), not one per column */
    grad = PyMem_Malloc((size_t)(w > 0 ? w : 1) * sizeof *grad);
    known = PyMem_Calloc((size_t)(w > 0 ? w : 1), 1);
    if (grad == NULL || known == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    result = PyList_New(0);
    if (result == NULL)
        goto done;
/* twice g at column x (0 <= x < w), computed on first use */
#define G(x)                                                                                   \
    (known[x] ? grad[x]                                                                        \
              : (known[x] = 1,                                                                 \
                 grad[x] = ((x) >= 1 && (x) + 1 < w)                                          \
                               ? ramp_twice_median(base, rows, rs, cs, (x))                    \
                               : 0L))
    for (Py_ssize_t i = 0; i < n_cols; i++) {
        Py_ssize_t c = PyLong_AsSsize_t(items[i]);
        if (c == -1 && PyErr_Occurred())
            goto fail;
        if (c < 0 || c >= w) {
            PyErr_SetString(PyExc_ValueError, "ramp_spans: a column outside the strip");
            goto fail;
        }
        Py_ssize_t lo = c - 1 > 0 ? c - 1 : 0, hi = c + 2 < w ? c + 2 : w;
        /* np.argmax of |g[lo:hi]|: the first of the largest */
        Py_ssize_t k = lo;
        long best = labs(G(lo));
        for (Py_ssize_t x = lo + 1; x < hi; x++) {
            long m = labs(G(x));
            if (m > best) {
                best = m;
                k = x;
            }
        }
        if (best == 0)
            continue;
        /* sg * g >= |peak| / 2, in doubled units: 2 * sg * G >= |G[k]| */
        const long sg = G(k) > 0 ? 1 : -1;
        Py_ssize_t a = k, b = k;
        while (a - 1 >= 0 && 2 * sg * G(a - 1) >= best)
            a--;
        while (b + 1 < w && 2 * sg * G(b + 1) >= best)
            b++;
        if (b - a + 1 < min_cols || a - beside < 0 || b + beside >= w)
            continue;
        PyObject *span = Py_BuildValue("(nnn)", c, a, b);
        if (span == NULL || PyList_Append(result, span) < 0) {
            Py_XDECREF(span);
            goto fail;
        }
        Py_DECREF(span);
    }
#undef G
    goto done;
fail:
    Py_CLEAR(result);
done:
    PyMem_Free(grad);
    PyMem_Free(known);
    PyBuffer_Release(&strip);
    Py_DECREF(cols);
    return result;
}

/* row_norms(x, out): profiles.row_norms (np.sqrt(np.add.reduce(x * x, axis=1))) of a 2-D
 * float32 or float64 array of rows of 1 to 7 values (any strides) into out (C-contiguous,
 * one value of x's type per row). Each square rounded to x's type, the squares added from
 * the left in it (numpy's reduce over fewer than 8 values adds them in order; its pairwise
 * sum starts at 8) and the root taken in it (IEEE square roots: correctly rounded, as
 * numpy's). ISO C99 (setup.py's -std=c99) contracts no multiply-add into an FMA. The
 * colour stages take ~50 norms of a few hundred Lab colours a frame: three numpy calls
 * each, here one. */
#define ROW_NORM_MAX 7
static PyObject *row_norms(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *x_obj, *out_obj;
    if (!PyArg_ParseTuple(args, "OO:row_norms", &x_obj, &out_obj))
        return NULL;
    Py_buffer x, out;
    if (PyObject_GetBuffer(x_obj, &x, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0) {
        PyBuffer_Release(&x);
        return NULL;
    }
    PyObject *result = NULL;
    const int f32 = x.format != NULL && strcmp(x.format, "f") == 0 && x.itemsize == 4;
    const int f64 = x.format != NULL && strcmp(x.format, "d") == 0 && x.itemsize == 8;
    if (x.ndim != 2 || !(f32 || f64) || x.shape[1] < 1 || x.shape[1] > ROW_NORM_MAX ||
        out.format == NULL || strcmp(out.format, x.format) != 0 || out.itemsize != x.itemsize ||
        out.len != x.shape[0] * out.itemsize) {
        PyErr_SetString(PyExc_TypeError,
                        "row_norms: a 2-D float32/float64 array of 1-7 columns, out of its type");
        goto done;
    }
    const Py_ssize_t rows = x.shape[0], cols = x.shape[1];
    const Py_ssize_t rs = x.strides[0], cs = x.strides[1];
    const char *base = (const char *)x.buf;
    if (f32) {
        float *o = (float *)out.buf;
        for (Py_ssize_t r = 0; r < rows; r++) {
            const char *p = base + r * rs;
            float v = *(const float *)p;
            float acc = v * v;
            for (Py_ssize_t c = 1; c < cols; c++) {
                v = *(const float *)(p + c * cs);
                float sq = v * v;
                acc = acc + sq;
            }
            o[r] = sqrtf(acc);
        }
    } else {
        double *o = (double *)out.buf;
        for (Py_ssize_t r = 0; r < rows; r++) {
            const char *p = base + r * rs;
            double v = *(const double *)p;
            double acc = v * v;
            for (Py_ssize_t c = 1; c < cols; c++) {
                v = *(const double *)(p + c * cs);
                double sq = v * v;
                acc = acc + sq;
            }
            o[r] = sqrt(acc);
        }
    }
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyBuffer_Release(&out);
    PyBuffer_Release(&x);
    return result;
}

/* A growing array of blocks (r0, r1, c0, c1). */
typedef struct {
    Py_ssize_t (*at)[4];
    Py_ssize_t n, cap;
} Blocks;

static int blocks_add(Blocks *b, Py_ssize_t r0, Py_ssize_t r1, Py_ssize_t c0, Py_ssize_t c1)
{
    if (b->n == b->cap) {
        Py_ssize_t cap = b->cap ? 2 * b->cap : 16;
        void *grown = PyMem_Realloc(b->at, (size_t)cap * sizeof *b->at);
        if (grown == NULL) {
            PyErr_NoMemory();
            return -1;
        }
        b->at = grown;
        b->cap = cap;
    }
    b->at[b->n][0] = r0;
    b->at[b->n][1] = r1;
    b->at[b->n][2] = c0;
    b->at[b->n][3] = c1;
    b->n++;
    return 0;
}

/* uncovered(boxes, r0, r1, c0, c1): View.lab's bookkeeping of a held frame's Lab blocks
 * (types.uncovered_pieces, the same steps): None when the block rows r0..r1-1, columns
 * c0..c1-1 lies inside one of ``boxes`` (a list of (r0, r1, c0, c1) tuples, the blocks
 * converted before); else the rectangles of it no box covers, as a list of such tuples
 * in the Python loop's order (the block less each box in turn: up to four pieces around
 * it). ~17 blocks a frame against up to a dozen boxes: the loop's interpreter steps cost
 * more than the test. The two piece lists are reused across boxes (one allocation each,
 * grown when needed). */
static PyObject *uncovered(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *boxes_obj;
    Py_ssize_t r0, r1, c0, c1;
    if (!PyArg_ParseTuple(args, "Onnnn:uncovered", &boxes_obj, &r0, &r1, &c0, &c1))
        return NULL;
    PyObject *boxes = PySequence_Fast(boxes_obj, "uncovered: boxes must be a sequence");
    if (boxes == NULL)
        return NULL;
    PyObject *result = NULL;
    const Py_ssize_t n = PySequence_Fast_GET_SIZE(boxes);
    PyObject **items = PySequence_Fast_ITEMS(boxes);
    Blocks have = {NULL, 0, 0}, rest = {NULL, 0, 0}, box = {NULL, 0, 0};
    for (Py_ssize_t i = 0; i < n; i++) {
        Py_ssize_t a, b, c, d;
        if (!PyTuple_Check(items[i])) {
            PyErr_SetString(PyExc_TypeError, "uncovered: each box a tuple (r0, r1, c0, c1)");
            goto done;
        }
        if (!PyArg_ParseTuple(items[i], "nnnn:uncovered", &a, &b, &c, &d) ||
            blocks_add(&box, a, b, c, d) < 0)
            goto done;
    }
    for (Py_ssize_t i = n - 1; i >= 0; i--) { /* inside one block before: the latest first */
        const Py_ssize_t *q = box.at[i];
        if (q[0] <= r0 && r1 <= q[1] && q[2] <= c0 && c1 <= q[3]) {
            Py_INCREF(Py_None);
            result = Py_None;
            goto done;
        }
    }
    if (blocks_add(&have, r0, r1, c0, c1) < 0)
        goto done;
    for (Py_ssize_t i = 0; i < n && have.n > 0; i++) {
        const Py_ssize_t a = box.at[i][0], b = box.at[i][1], c = box.at[i][2], d = box.at[i][3];
        rest.n = 0;
        for (Py_ssize_t k = 0; k < have.n; k++) {
            const Py_ssize_t p0 = have.at[k][0], p1 = have.at[k][1];
            const Py_ssize_t q0 = have.at[k][2], q1 = have.at[k][3];
            int failed = 0;
            if (a >= p1 || b <= p0 || c >= q1 || d <= q0) {
                failed |= blocks_add(&rest, p0, p1, q0, q1);
            } else {
                const Py_ssize_t m0 = p0 > a ? p0 : a, m1 = p1 < b ? p1 : b;
                if (p0 < a)
                    failed |= blocks_add(&rest, p0, a, q0, q1);
                if (b < p1)
                    failed |= blocks_add(&rest, b, p1, q0, q1);
                if (q0 < c)
                    failed |= blocks_add(&rest, m0, m1, q0, c);
                if (d < q1)
                    failed |= blocks_add(&rest, m0, m1, d, q1);
            }
            if (failed)
                goto done;
        }
        Blocks swap = have;
        have = rest;
        rest = swap;
    }
    result = PyList_New(have.n);
    if (result == NULL)
        goto done;
    for (Py_ssize_t k = 0; k < have.n; k++) {
        PyObject *piece = Py_BuildValue("(nnnn)", have.at[k][0], have.at[k][1], have.at[k][2],
                                        have.at[k][3]);
        if (piece == NULL) {
            Py_CLEAR(result);
            goto done;
        }
        PyList_SET_ITEM(result, k, piece);
    }
done:
    PyMem_Free(have.at);
    PyMem_Free(rest.at);
    PyMem_Free(box.at);
    Py_DECREF(boxes);
    return result;
}

/* score_tops(ay, ax3, counts, nxt, grey, pairs, bands, noise, rb, top_limit, kf,
 * label_rows, label_share, tops, pp, f64, f32, i32): scoring.score_pairs' top candidates
 * and their features, the numpy path's values bit for bit (the same float32 and float64
 * operations in the same order; sums of integers, exact in either order).
 *
 * pairs: int64, one row per pair: ul, ur, c0, c1 (the inner columns), the side table
 * columns il, ir, their edge runs' tops, and the background columns ba, bb (Sides).
 * bands: how many column bands across each pair's inner columns (scoring.band_ranges').
 * counts: Sides' running counts (upto, out), nxt: its next edge rows. grey: the working
 * view's grey rows (0..rb-1 read). The top candidates go to tops and
 * pp (pair-major, rows ascending) and their features to the rows of f64 (cov, stop, hole,
 * textured, tex_above, face, face_above, face_bands), f32 (snr, contained) and i32 (up_l,
 * up_r), each of the outputs' capacity long (at least top_limit entries per pair). Returns
 * the number of top candidates. */
#define SCORE_PAIR_FIELDS 10
#define SCORE_MAX_BANDS 16
#define SCORE_MAX_KF 64

#define AT2(b, type, r, c)                                                                   \
    (*(const type *)((const char *)(b).buf + (Py_ssize_t)(r) * (b).strides[0] +             \
                     (Py_ssize_t)(c) * (b).strides[1]))

static int has_format(const Py_buffer *b, Py_ssize_t itemsize, const char *formats)
{
    if (b->itemsize != itemsize || b->format == NULL)
        return 0;
    const char *f = b->format;
    if (*f == '=' || *f == '@' || *f == '<')
        f++;
    return f[0] != '\0' && f[1] == '\0' && strchr(formats, f[0]) != NULL;
}

/* 16 zero bytes, then 16 of all ones: the 16 bytes from entry k keep the last k bytes
 * of a vector (a range's last k < 16 bytes, or 4-byte floats, read as the end of a
 * whole vector ending at the range's end, the lanes before it masked off). */
static const unsigned char last_lanes[32] = {
    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,    0,
    0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff};

/* The sum of row r's floats over columns c0..c1-1: exact for the integer-valued gradients
 * summed here (|d/dy| <= 1020 over at most a row: every partial sum an integer under 2**24,
 * exact in float32 lanes and in double), so the same value in any order, cv2.reduce's
 * included. Four lanes at a time where the row is packed. */
static double row_sum_f32(const Py_buffer *b, Py_ssize_t r, Py_ssize_t c0, Py_ssize_t c1)
{
    const char *row = (const char *)b->buf + r * b->strides[0];
    Py_ssize_t cs = b->strides[1];
    double s = 0.0;
    Py_ssize_t c = c0;
#ifdef __SSE2__
    if (cs == (Py_ssize_t)sizeof(float)) {
        const float *p = (const float *)row;
        __m128 a0 = _mm_setzero_ps(), a1 = _mm_setzero_ps();
        for (; c + 8 <= c1; c += 8) {
            a0 = _mm_add_ps(a0, _mm_loadu_ps(p + c));
            a1 = _mm_add_ps(a1, _mm_loadu_ps(p + c + 4));
        }
        for (; c + 4 <= c1; c += 4)
            a0 = _mm_add_ps(a0, _mm_loadu_ps(p + c));
        if (c < c1 && c1 >= 4) {
            /* the last 1-3 floats: the 4 ending at c1, those before c masked off (read
             * inside the row: c1 >= 4) */
            __m128 keep = _mm_loadu_ps((const float *)(last_lanes + 4 * (c1 - c)));
            a1 = _mm_add_ps(a1, _mm_and_ps(_mm_loadu_ps(p + c1 - 4), keep));
            c = c1;
        }
        float lanes[4];
        _mm_storeu_ps(lanes, _mm_add_ps(a0, a1));
        s = ((double)lanes[0] + lanes[1]) + ((double)lanes[2] + lanes[3]);
    }
#endif
    for (; c < c1; c++)
        s += *(const float *)(row + c * cs);
    return s;
}

/* The sum of row r's int16 values over columns c0..c1-1 (integers: exact in any order);
 * eight at a time where the row is packed. */
static long row_sum_i16(const Py_buffer *b, Py_ssize_t r, Py_ssize_t c0, Py_ssize_t c1)
{
    const char *row = (const char *)b->buf + r * b->strides[0];
    Py_ssize_t cs = b->strides[1];
    long s = 0;
    Py_ssize_t c = c0;
#ifdef __SSE2__
    if (cs == (Py_ssize_t)sizeof(short)) {
        const short *p = (const short *)row;
        const __m128i ones = _mm_set1_epi16(1);
        __m128i acc = _mm_setzero_si128();
        /* pairs of int16 summed into int32 lanes: at most 2 * 32768 a step, a row of
         * under 2**15 steps */
        for (; c + 8 <= c1; c += 8)
            acc = _mm_add_epi32(acc, _mm_madd_epi16(_mm_loadu_si128((const __m128i *)(p + c)), ones));
        if (c < c1 && c1 >= 8) {
            /* the last 1-7 values: the 8 ending at c1 (inside the row), those before c
             * masked off */
            __m128i keep = _mm_loadu_si128((const __m128i *)(last_lanes + 2 * (c1 - c)));
            __m128i tail = _mm_loadu_si128((const __m128i *)(p + c1 - 8));
            acc = _mm_add_epi32(acc, _mm_madd_epi16(_mm_and_si128(tail, keep), ones));
            c = c1;
        }
        int lanes[4];
        _mm_storeu_si128((__m128i *)lanes, acc);
        s = (long)lanes[0] + lanes[1] + lanes[2] + lanes[3];
    }
#endif
    for (; c < c1; c++)
        s += *(const short *)(row + c * cs);
    return s;
}

/* The kth smallest of n floats (n <= SCORE_MAX_KF): numpy's partition's value. */
static float kth_smallest(const float *x, int n, int k)
{
    float s[SCORE_MAX_KF];
    for (int i = 0; i < n; i++) {
        float v = x[i];
        int j = i;
        for (; j > 0 && s[j - 1] > v; j--)
            s[j] = s[j - 1];
        s[j] = v;
    }
    return s[k];
}

/* A column of shade matches: running counts cnt[0..rb] and next match first[0..rb-1]. */
static void match_column(const unsigned char *match, Py_ssize_t rb, int *cnt, Py_ssize_t *first)
{
    cnt[0] = 0;
    for (Py_ssize_t r = 0; r < rb; r++)
        cnt[r + 1] = cnt[r] + match[r];
    Py_ssize_t low = rb;
    for (Py_ssize_t r = rb - 1; r >= 0; r--) {
        if (match[r])
            low = r;
        first[r] = low;
    }
}

/* scoring._shade_share of one top candidate in one column. */
static double shade_share(const int *cnt, const Py_ssize_t *first, Py_ssize_t rb, Py_ssize_t t,
                          Py_ssize_t h, long label_rows, double label_share)
{
    double share = (double)(cnt[rb] - cnt[t]) / (double)h;
    Py_ssize_t ft = first[t];
    long long inner = (long long)(rb - ft) - (long long)(cnt[rb] - cnt[ft]);
    if (ft - t <= label_rows && (double)inner <= label_share * (double)h)
        return share + (double)inner / (double)h;
    return share;
}

/* The sum of row r's bytes over columns c0..c1-1; sixteen at a time where the row is
 * packed. */
static long row_sum_u8(const Py_buffer *b, Py_ssize_t r, Py_ssize_t c0, Py_ssize_t c1)
{
    const unsigned char *row = (const unsigned char *)b->buf + r * b->strides[0];
    Py_ssize_t cs = b->strides[1];
    long s = 0;
    Py_ssize_t c = c0;
#ifdef __SSE2__
    if (cs == 1 && c1 >= 16) {
        const __m128i zero = _mm_setzero_si128();
        __m128i acc = zero;
        for (; c + 16 <= c1; c += 16)
            acc = _mm_add_epi64(acc, _mm_sad_epu8(_mm_loadu_si128((const __m128i *)(row + c)), zero));
        if (c < c1) {
            /* the last 1-15 bytes: the 16 ending at c1 (inside the row), those before c
             * masked off */
            __m128i keep = _mm_loadu_si128((const __m128i *)(last_lanes + (c1 - c)));
            __m128i tail = _mm_loadu_si128((const __m128i *)(row + c1 - 16));
            acc = _mm_add_epi64(acc, _mm_sad_epu8(_mm_and_si128(tail, keep), zero));
            c = c1;
        }
        long long lanes[2];
        _mm_storeu_si128((__m128i *)lanes, acc);
        s = (long)(lanes[0] + lanes[1]);
    }
#endif
    for (; c < c1; c++)
        s += row[c * cs];
    return s;
}

static PyObject *score_tops(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *objs[11];
    double noise, label_share;
    Py_ssize_t n_b, rb, top_limit, kf;
    long label_rows;
    if (!PyArg_ParseTuple(args, "OOOOOOndnnnldOOOOO:score_tops", &objs[0], &objs[1], &objs[2],
                          &objs[3], &objs[4], &objs[5], &n_b, &noise, &rb, &top_limit, &kf,
                          &label_rows, &label_share, &objs[6], &objs[7], &objs[8], &objs[9],
                          &objs[10]))
        return NULL;
    Py_buffer b[11];
    int got = 0;
    for (; got < 11; got++) {
        int flags = got < 6 ? PyBUF_STRIDES | PyBUF_FORMAT
                            : PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT;
        if (PyObject_GetBuffer(objs[got], &b[got], flags) < 0)
            break;
    }
    PyObject *result = NULL;
    float *prof = NULL, *gsum = NULL;
    int *work = NULL;
    Py_ssize_t *firsts = NULL;
    unsigned char *match = NULL;
    if (got < 11)
        goto done;
    Py_buffer *ay = &b[0], *ax3 = &b[1], *counts = &b[2], *nxt = &b[3], *grey = &b[4];
    Py_buffer *pairs = &b[5];
    if (!has_format(ay, 4, "f") || !has_format(ax3, 2, "h") || !has_format(counts, 4, "i") ||
        !has_format(nxt, 8, "lq") || !is_u8(grey) || !has_format(pairs, 8, "lq") ||
        !has_format(&b[6], 8, "lq") || !has_format(&b[7], 8, "lq") ||
        !has_format(&b[8], 8, "d") || !has_format(&b[9], 4, "f") || !has_format(&b[10], 4, "i") ||
        ay->ndim != 2 || ax3->ndim != 2 || counts->ndim != 2 || nxt->ndim != 2 ||
        grey->ndim != 2 || pairs->ndim != 2 || pairs->shape[1] != SCORE_PAIR_FIELDS) {
        PyErr_SetString(PyExc_TypeError, "score_tops: arrays of the wrong type or shape");
        goto done;
    }
    Py_ssize_t n_p = pairs->shape[0];
    Py_ssize_t cap = b[6].len / 8;
    Py_ssize_t w = ay->shape[1];
    if (n_p < 1 || n_b < 1 || n_b > SCORE_MAX_BANDS || top_limit < 3 || rb <= top_limit ||
        kf < 2 || kf > SCORE_MAX_KF || rb - 3 - kf < 0 || top_limit > ay->shape[0] ||
        rb > ax3->shape[0] || ax3->shape[1] != w || rb > grey->shape[0] ||
        grey->shape[1] != w || counts->shape[0] < rb + 1 || nxt->shape[0] < rb ||
        cap < n_p * top_limit || b[7].len / 8 != cap || b[8].len / 8 < 8 * cap ||
        b[9].len / 4 < 2 * cap || b[10].len / 4 < 2 * cap) {
        PyErr_SetString(PyExc_ValueError, "score_tops: sizes that do not fit");
        goto done;
    }
    Py_ssize_t n_cols = counts->shape[1], n_side = nxt->shape[1];
    for (Py_ssize_t j = 0; j < n_p; j++) {
        long long p[SCORE_PAIR_FIELDS];
        for (int f = 0; f < SCORE_PAIR_FIELDS; f++)
            p[f] = AT2(*pairs, long long, j, f);
        int bad = p[0] < 0 || p[1] > w || p[0] >= p[1] || p[2] < 0 || p[3] > w || p[2] >= p[3];
        for (int f = 4; f < 6; f++)
            bad |= p[f] < 0 || p[f] >= n_side;
        for (int f = 8; f < 10; f++)
            bad |= p[f] < 0 || p[f] >= n_cols;
        /* the last band is one column wide at least: past c1 on the narrowest pairs */
        bad |= p[3] + 1 > w;
        if (bad) {
            PyErr_SetString(PyExc_ValueError, "score_tops: a pair's columns out of range");
            goto done;
        }
    }
    prof = PyMem_Malloc((size_t)(n_p * top_limit) * sizeof(float));
    /* per column of shade matches (the face's, then its bands'): counts and next match;
     * then per pair the texture counts */
    Py_ssize_t n_q = 1 + n_b;
    gsum = PyMem_Malloc((size_t)(n_q * rb) * sizeof(float));
    work = PyMem_Malloc((size_t)(n_q * (rb + 1) + (rb + 1)) * sizeof(int));
    firsts = PyMem_Malloc((size_t)(n_q * rb) * sizeof(Py_ssize_t));
    match = PyMem_Malloc((size_t)rb);
    if (prof == NULL || gsum == NULL || work == NULL || firsts == NULL || match == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    const float nf = (float)noise;
    long long *tops = (long long *)b[6].buf, *pp = (long long *)b[7].buf;
    double *f64 = (double *)b[8].buf;
    float *f32 = (float *)b[9].buf;
    int *i32 = (int *)b[10].buf;
    /* the mean |d/dy| between each pair's sides, rows 0..top_limit-1, and its peaks */
    Py_ssize_t n_t = 0;
    for (Py_ssize_t j = 0; j < n_p; j++) {
        Py_ssize_t c0 = (Py_ssize_t)AT2(*pairs, long long, j, 2);
        Py_ssize_t c1 = (Py_ssize_t)AT2(*pairs, long long, j, 3);
        float inv_n = (float)(1.0 / (double)(c1 - c0));
        float *pr = prof + j * top_limit;
        for (Py_ssize_t r = 0; r < top_limit; r++)
            pr[r] = (float)row_sum_f32(ay, r, c0, c1) * inv_n;
        long long e[2] = {AT2(*pairs, long long, j, 6), AT2(*pairs, long long, j, 7)};
        for (Py_ssize_t r = 0; r < top_limit; r++) {
            int on = 0;
            if (r >= 1 && r <= top_limit - 2) {
                float s = pr[r] / nf, up = pr[r - 1] / nf, down = pr[r + 1] / nf;
                on = s >= up && s > down && s > 1.2f;
            }
            for (int q = 0; q < 2 && !on; q++)
                on = r > 0 && (r == e[q] - 1 || r == e[q]);
            if (on) {
                tops[n_t] = r;
                pp[n_t] = j;
                n_t++;
            }
        }
    }
    Py_ssize_t t0 = rb;
    for (Py_ssize_t i = 0; i < n_t; i++) {
        Py_ssize_t t = tops[i], h = rb - t;
        Py_ssize_t a = t - (h / 2 > 3 ? h / 2 : 3);
        if (a < 0)
            a = 0;
        if (a < t0)
            t0 = a;
    }
    const float tex_min = (float)(3.0 * noise);
    const double grey_noise = (noise - 1.0 > 0.0 ? noise - 1.0 : 0.0) / 3.46;
    const float grey_tol = (float)(3.0 * grey_noise);
    int *texc = work + n_q * (rb + 1);
    Py_ssize_t i = 0;
    for (Py_ssize_t j = 0; j < n_p; j++) {
        Py_ssize_t s0 = i;
        while (i < n_t && pp[i] == j)
            i++;
        if (i == s0)
            continue;
        Py_ssize_t ul = (Py_ssize_t)AT2(*pairs, long long, j, 0);
        Py_ssize_t ur = (Py_ssize_t)AT2(*pairs, long long, j, 1);
        Py_ssize_t c0 = (Py_ssize_t)AT2(*pairs, long long, j, 2);
        Py_ssize_t c1 = (Py_ssize_t)AT2(*pairs, long long, j, 3);
        Py_ssize_t il = (Py_ssize_t)AT2(*pairs, long long, j, 4);
        Py_ssize_t ir = (Py_ssize_t)AT2(*pairs, long long, j, 5);
        Py_ssize_t ba = (Py_ssize_t)AT2(*pairs, long long, j, 8);
        Py_ssize_t bb = (Py_ssize_t)AT2(*pairs, long long, j, 9);
        float inv_n = (float)(1.0 / (double)(c1 - c0));
        const float *pr = prof + j * top_limit;
        /* texture rows (t0..rb-1) and their running counts from t0 */
        texc[t0] = 0;
        for (Py_ssize_t r = t0; r < rb; r++) {
            long s = row_sum_i16(ax3, r, c0, c1);
            texc[r + 1] = texc[r] + ((float)s * inv_n > tex_min);
        }
        /* the columns just outside each side */
        Py_ssize_t wo = (ur - ul) / 5 > 3 ? (ur - ul) / 5 : 3;
        Py_ssize_t o0 = ul - 1 - wo > 0 ? ul - 1 - wo : 0, o1 = ul - 1 > 1 ? ul - 1 : 1;
        Py_ssize_t o2 = ur + 2 < w - 1 ? ur + 2 : w - 1, o3 = ur + 2 + wo < w ? ur + 2 + wo : w;
        float inv_l = (float)(1.0 / (double)(o1 - o0)), inv_r = (float)(1.0 / (double)(o3 - o2));
        /* the column bands [lo, hi) across the inner columns: c0 + round(b (c1 - c0) /
         * BANDS), rounded half to even (as scoring.band_ranges), each a column wide at least;
         * a tiling of c0..c1 unless the pair is narrower than the bands */
        Py_ssize_t lo[SCORE_MAX_BANDS], hi[SCORE_MAX_BANDS];
        int tiled = 1;
        for (Py_ssize_t q = 0; q < n_b; q++) {
            lo[q] = c0 + (Py_ssize_t)nearbyint((double)(q * (c1 - c0)) / (double)n_b);
            Py_ssize_t end = c0 + (Py_ssize_t)nearbyint((double)((q + 1) * (c1 - c0)) / (double)n_b);
            hi[q] = end > lo[q] + 1 ? end : lo[q] + 1;
            tiled &= end > lo[q];
        }
        /* the grey row sums over the inner columns (gsum, rows 0..rb-1), then over each band
         * (integers: exact in float32, as numpy's) */
        for (Py_ssize_t r = 0; r < rb; r++) {
            long whole = 0;
            for (Py_ssize_t q = 0; q < n_b; q++) {
                long s = row_sum_u8(grey, r, lo[q], hi[q]);
                gsum[(q + 1) * rb + r] = (float)s;
                whole += s;
            }
            gsum[r] = (float)(tiled ? whole : row_sum_u8(grey, r, c0, c1));
        }
        /* the face's shade (whole width, then each band) and the rows that match it */
        for (Py_ssize_t q = 0; q < n_q; q++) {
            const float *gq = gsum + q * rb;
            float width = q > 0 ? (float)(hi[q - 1] - lo[q - 1]) : 0.0f;
            float means[SCORE_MAX_KF];
            for (Py_ssize_t r = rb - 3 - kf; r < rb - 3; r++) {
                float g = gq[r];
                means[r - (rb - 3 - kf)] = q == 0 ? g * inv_n : g / width;
            }
            float face = kth_smallest(means, (int)kf, (int)(kf / 2));
            float tol;
            if (q == 0) {
                float rel = (float)(0.08 * (double)face);
                tol = rel > 8.0f ? rel : 8.0f;
            } else {
                float rel = 0.08f * face;
                float t1 = rel > 8.0f ? rel : 8.0f;
                float t2 = grey_tol / sqrtf(width);
                tol = t1 > t2 ? t1 : t2;
            }
            for (Py_ssize_t r = 0; r < rb; r++) {
                float g = gq[r];
                float m = q == 0 ? g * inv_n : g / width;
                match[r] = fabsf(m - face) <= tol;
            }
            match_column(match, rb, work + q * (rb + 1), firsts + q * rb);
        }
        const int *mc = work;
        const Py_ssize_t *mf = firsts;
        for (Py_ssize_t k = s0; k < i; k++) {
            Py_ssize_t t = tops[k], h = rb - t;
            double span = (double)h;
            int below_l = AT2(*counts, int, rb, il) - AT2(*counts, int, t, il);
            int below_r = AT2(*counts, int, rb, ir) - AT2(*counts, int, t, ir);
            double cov = 0.5 * (double)(below_l + below_r) / span;
            Py_ssize_t as = t - (h / 2 > 3 ? h / 2 : 3);
            if (as < 0)
                as = 0;
            Py_ssize_t n_above = t - as > 1 ? t - as : 1;
            int ext = (AT2(*counts, int, t, il) + AT2(*counts, int, t, ir)) -
                      (AT2(*counts, int, as, il) + AT2(*counts, int, as, ir));
            double above = 0.5 * (double)ext / (double)n_above;
            int bg = (AT2(*counts, int, t, ba) + AT2(*counts, int, t, bb)) -
                     (AT2(*counts, int, as, ba) + AT2(*counts, int, as, bb));
            above = above - 0.5 * (double)bg / (double)n_above;
            if (!(above > 0.0))
                above = 0.0;
            Py_ssize_t start = t + 1 < rb - 1 ? t + 1 : rb - 1;
            long long nx = AT2(*nxt, long long, start, il) + AT2(*nxt, long long, start, ir) -
                           2 * (long long)start;
            double hole = 0.5 * (double)nx;
            float o_l = (float)row_sum_f32(ay, t, o0, o1) * inv_l;
            float o_r = (float)row_sum_f32(ay, t, o2, o3) * inv_r;
            float inside = pr[t] > 1e-3f ? pr[t] : 1e-3f;
            float cont = 1.0f - (o_l > o_r ? o_l : o_r) / inside;
            cont = cont > 0.0f ? cont : 0.0f;
            cont = cont < 1.0f ? cont : 1.0f;
            double textured = (double)(texc[rb] - texc[t]) / (double)h;
            double tex_above = (double)(texc[t] - texc[as]) / (double)n_above;
            double face = shade_share(mc, mf, rb, t, h, label_rows, label_share);
            Py_ssize_t a0 = t - (h > 3 ? h : 3);
            if (a0 < 0)
                a0 = 0;
            double face_above =
                (double)(mc[t] - mc[a0]) / (double)(t - a0 > 1 ? t - a0 : 1);
            Py_ssize_t t2 = t - 2 > 0 ? t - 2 : 0;
            /* (a row matches where its next match is itself) */
            if (mf[t - 1] == t - 1 || mf[t2] == t2)
                face_above = 0.0;
            double bands_min = 0.0;
            for (Py_ssize_t q = 1; q < n_q; q++) {
                double s = shade_share(work + q * (rb + 1), firsts + q * rb, rb, t, h,
                                       label_rows, label_share);
                if (q == 1 || s < bands_min)
                    bands_min = s;
            }
            f64[0 * cap + k] = cov;
            f64[1 * cap + k] = 1.0 - above;
            f64[2 * cap + k] = hole;
            f64[3 * cap + k] = textured;
            f64[4 * cap + k] = tex_above;
            f64[5 * cap + k] = face;
            f64[6 * cap + k] = face_above;
            f64[7 * cap + k] = bands_min;
            f32[0 * cap + k] = pr[t] / nf;
            f32[1 * cap + k] = cont;
            i32[0 * cap + k] = AT2(*counts, int, t, il);
            i32[1 * cap + k] = AT2(*counts, int, t, ir);
        }
    }
    result = PyLong_FromSsize_t(n_t);
done:
    PyMem_Free(match);
    PyMem_Free(firsts);
    PyMem_Free(work);
    PyMem_Free(gsum);
    PyMem_Free(prof);
    for (int k = got - 1; k >= 0; k--)
        PyBuffer_Release(&b[k]);
    return result;
}

/* project3(src, m0, m1, m2, m3, dst): cv2.transform(src, [[m0, m1, m2, m3]]) of a BGR
 * image (rows x columns x 3 uint8, pixels packed) into dst (rows x columns uint8), the
 * same integers: OpenCV's 3-to-1 channel loop, m0*b + m1*g + m2*r + m3 in float32 rounded
 * to the nearest (ties to even) and saturated, as its dispatched build computes it here
 * (contracted to fused multiply-adds: fma(m2, r, fma(m0, b, m1*g)) + m3; checked on every
 * 8-bit colour, tests/vision/test_face_floor_grey.py). The fused multiply-adds are exact in
 * double (every product and sum is a multiple of 2**-43 under 2**10 in magnitude when
 * each |m| lies in 2**-20..16 or is 0, which the caller checks), rounded once to float.
 * The per-channel products come from 256-entry tables; ~16 instructions a pixel against
 * OpenCV's ~27 here. */
static PyObject *project3(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *src_obj, *dst_obj;
    double m[4];
    if (!PyArg_ParseTuple(args, "OddddO:project3", &src_obj, &m[0], &m[1], &m[2], &m[3],
                          &dst_obj))
        return NULL;
    for (int k = 0; k < 3; k++) {
        double a = fabs(m[k]);
        if ((float)m[k] != m[k] || (a != 0.0 && (a < 0x1p-20 || a > 16.0))) {
            PyErr_SetString(PyExc_ValueError, "project3: weights of float32, 2**-20..16 or 0");
            return NULL;
        }
    }
    if ((float)m[3] != m[3] || fabs(m[3]) > 8192.0) {
        PyErr_SetString(PyExc_ValueError, "project3: an offset of float32 within 8192");
        return NULL;
    }
    Py_buffer src, dst;
    if (PyObject_GetBuffer(src_obj, &src, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(dst_obj, &dst, PyBUF_STRIDES | PyBUF_FORMAT | PyBUF_WRITABLE) < 0) {
        PyBuffer_Release(&src);
        return NULL;
    }
    PyObject *result = NULL;
    if (!is_u8(&src) || !is_u8(&dst) || src.ndim != 3 || dst.ndim != 2 || src.shape[2] != 3 ||
        src.strides[2] != 1 || src.strides[1] != 3 || dst.strides[1] != 1 ||
        dst.shape[0] != src.shape[0] || dst.shape[1] != src.shape[1]) {
        PyErr_SetString(PyExc_ValueError, "project3: a packed BGR image and a grey one of its size");
        goto done;
    }
    double pb[256], pg[256], pr[256];
    const float m1 = (float)m[1], m3 = (float)m[3];
    for (int v = 0; v < 256; v++) {
        pb[v] = m[0] * v;             /* exact: 24 by 8 bits */
        pg[v] = (double)(m1 * (float)v); /* the float product, rounded as OpenCV's */
        pr[v] = m[2] * v;
    }
    const Py_ssize_t rows = src.shape[0], cols = src.shape[1];
    for (Py_ssize_t r = 0; r < rows; r++) {
        const unsigned char *restrict p = (const unsigned char *)src.buf + r * src.strides[0];
        unsigned char *restrict out = (unsigned char *)dst.buf + r * dst.strides[0];
        Py_ssize_t c = 0;
#ifdef __SSE2__
        /* four pixels at a time: two in each pair of double lanes, the rounding to float
         * and the final float sum and rounding as the scalar loop's (MXCSR: to nearest) */
        const __m128 off = _mm_set1_ps(m3);
        for (; c + 4 <= cols; c += 4, p += 12) {
            __m128 lo = _mm_cvtpd_ps(_mm_add_pd(_mm_set_pd(pb[p[3]], pb[p[0]]),
                                                _mm_set_pd(pg[p[4]], pg[p[1]])));
            __m128 hi = _mm_cvtpd_ps(_mm_add_pd(_mm_set_pd(pb[p[9]], pb[p[6]]),
                                                _mm_set_pd(pg[p[10]], pg[p[7]])));
            lo = _mm_cvtpd_ps(_mm_add_pd(_mm_set_pd(pr[p[5]], pr[p[2]]), _mm_cvtps_pd(lo)));
            hi = _mm_cvtpd_ps(_mm_add_pd(_mm_set_pd(pr[p[11]], pr[p[8]]), _mm_cvtps_pd(hi)));
            __m128i v = _mm_cvtps_epi32(_mm_add_ps(_mm_movelh_ps(lo, hi), off));
            v = _mm_packs_epi32(v, v);
            int bytes = _mm_cvtsi128_si32(_mm_packus_epi16(v, v));
            memcpy(out + c, &bytes, 4);
        }
#endif
        for (; c < cols; c++, p += 3) {
            float t = (float)(pb[p[0]] + pg[p[1]]);
            t = (float)(pr[p[2]] + (double)t);
            long v = lrintf(t + m3); /* to nearest, ties to even (cvRound) */
            out[c] = (unsigned char)(v < 0 ? 0 : v > 255 ? 255 : v);
        }
    }
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyBuffer_Release(&dst);
    PyBuffer_Release(&src);
    return result;
}

/* kth_counted(src, k): the k-th smallest (0-based) value of src (float32, 1-D or 2-D, any
 * strides) as a Python float, when every value is a whole number in 0..KTH_COUNTED_MAX
 * (the frame's |d/dy|, under 1021): read off counts of its values, exactly the value a
 * partition (profiles.median's) leaves at k. None when a value is not such a number
 * (negative zero, fractions, NaN, larger: the caller partitions), or for a k outside
 * 0..size-1. */
#define KTH_COUNTED_MAX 1023
static PyObject *kth_counted(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *src_obj;
    Py_ssize_t k;
    if (!PyArg_ParseTuple(args, "On:kth_counted", &src_obj, &k))
        return NULL;
    Py_buffer src;
    if (PyObject_GetBuffer(src_obj, &src, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    PyObject *result = NULL;
    if (src.itemsize != 4 || src.format == NULL || strcmp(src.format, "f") != 0 ||
        src.ndim < 1 || src.ndim > 2) {
        PyErr_SetString(PyExc_TypeError, "kth_counted: a 1-D or 2-D float32 array");
        goto done;
    }
    Py_ssize_t rows = src.ndim == 2 ? src.shape[0] : 1, cols = src.shape[src.ndim - 1];
    Py_ssize_t rs = src.ndim == 2 ? src.strides[0] : 0, cs = src.strides[src.ndim - 1];
    if (k < 0 || k >= rows * cols) {
        Py_INCREF(Py_None);
        result = Py_None;
        goto done;
    }
    Py_ssize_t count[KTH_COUNTED_MAX + 1];
    memset(count, 0, sizeof count);
    for (Py_ssize_t r = 0; r < rows; r++) {
        const char *row = (const char *)src.buf + r * rs;
        for (Py_ssize_t c = 0; c < cols; c++) {
            float x;
            memcpy(&x, row + c * cs, sizeof x);
            /* (NaN fails the first test; -0.0 passes it and is refused by its sign) */
            if (!(x >= 0.0f && x <= (float)KTH_COUNTED_MAX) || signbit(x)) {
                Py_INCREF(Py_None);
                result = Py_None;
                goto done;
            }
            int v = (int)x;
            if ((float)v != x) {
                Py_INCREF(Py_None);
                result = Py_None;
                goto done;
            }
            count[v]++;
        }
    }
    Py_ssize_t below = 0;
    int v = 0;
    for (; v < KTH_COUNTED_MAX; v++) {
        below += count[v];
        if (below > k)
            break;
    }
    result = PyFloat_FromDouble((double)v);
done:
    PyBuffer_Release(&src);
    return result;
}

/* One candidate in rank_sides' rankings: its value and where it came from. */
typedef struct {
    double v;
    Py_ssize_t at;
} Ranked;

/* Into best[0..*len) (descending by v, at most keep + 1 entries), a candidate: after those
 * of equal value (the order of a stable sort), dropped past the kept places. */
static void rank_insert(Ranked *best, Py_ssize_t *len, Py_ssize_t keep, double v, Py_ssize_t at)
{
    Py_ssize_t pos = *len;
    while (pos > 0 && best[pos - 1].v < v)
        pos--;
    if (pos > keep)
        return;
    Py_ssize_t end = *len < keep + 1 ? *len : keep;
    for (Py_ssize_t i = end; i > pos; i--)
        best[i] = best[i - 1];
    best[pos] = (Ranked){v, at};
    if (*len < keep + 1)
        (*len)++;
}

/* Whether two equal values hold places from..keep of a ranking (the last kept place and
 * the one after included): numpy's sort (not stable) may order them either way. */
static int rank_tied(const Ranked *best, Py_ssize_t len, Py_ssize_t from, Py_ssize_t keep)
{
    for (Py_ssize_t p = from; p + 1 < len && p < keep; p++)
        if (best[p].v == best[p + 1].v)
            return 1;
    return 0;
}

/* A group of columns (1-D int64) as a buffer; 0 with an error set if it is none. */
static int int64_column_buffer(PyObject *obj, Py_buffer *b)
{
    if (PyObject_GetBuffer(obj, b, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return 0;
    if (b->ndim != 1 || !has_format(b, 8, "lq")) {
        PyBuffer_Release(b);
        PyErr_SetString(PyExc_TypeError, "rank_sides: each group a 1-D int64 array");
        return 0;
    }
    return 1;
}

/* rank_sides(ax3, prof_v, prof_short, groups, rb, cap, low, late_rows, keep):
 * search._rank_sides whole, one call a side search. Per group of peak columns (1-D int64),
 * its 3 * keep strongest by prof_v (float32); for all of them the edge run up from row
 * rb - 2 in ax3 (int16) above the presence threshold floor(max(min(0.25 * prof_short,
 * cap), low)) taken in float32 as numpy's (cap, low: PRESENCE_CAP * noise and 2.5 * noise,
 * rounded to float32 as numpy rounds a Python float), its length to the first gap of 3
 * misses (profiles.first_gap) and, for a column with no run from the floor, its late run
 * (profiles.late_run); ranks prof_v * sqrt(run) in float64 (late runs' ranks below every
 * other, as the numpy path: minus their maximum plus 1); per group the keep best of
 * those with a run of 3 rows or more, as lists of ints. None where numpy's (unstable) sort
 * could order a tie either way (two equal ranks among a group's keep best, or equal
 * prof_v across its 3 * keep-th place: a tie within those places orders only what the
 * distinct ranks then order again), or where a column or rb falls outside the arrays (rb < 2
 * included: the
 * caller ranks in numpy then: the same values otherwise, bit for bit). */
static PyObject *rank_sides(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *ax_obj, *pv_obj, *ps_obj, *groups_obj;
    Py_ssize_t rb, late_rows, keep;
    double cap, low;
    if (!PyArg_ParseTuple(args, "OOOOnddnn:rank_sides", &ax_obj, &pv_obj, &ps_obj, &groups_obj,
                          &rb, &cap, &low, &late_rows, &keep))
        return NULL;
    if (keep < 1) {
        PyErr_SetString(PyExc_ValueError, "rank_sides: keep must be at least 1");
        return NULL;
    }
    PyObject *groups = PySequence_Fast(groups_obj, "rank_sides: groups must be a sequence");
    if (groups == NULL)
        return NULL;
    const Py_ssize_t n_groups = PySequence_Fast_GET_SIZE(groups);
    PyObject **items = PySequence_Fast_ITEMS(groups);
    Py_buffer ax, pv, ps;
    Py_buffer *gb = PyMem_Calloc((size_t)(n_groups > 0 ? n_groups : 1), sizeof *gb);
    Py_ssize_t held = 0; /* group buffers acquired */
    int have_ax = 0, have_pv = 0, have_ps = 0;
    PyObject *result = NULL;
    Ranked *best = NULL;
    Py_ssize_t *cols = NULL, *starts = NULL, *run = NULL, *late = NULL;
    double *rank = NULL;
    if (gb == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    if (PyObject_GetBuffer(ax_obj, &ax, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        goto done;
    have_ax = 1;
    if (PyObject_GetBuffer(pv_obj, &pv, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        goto done;
    have_pv = 1;
    if (PyObject_GetBuffer(ps_obj, &ps, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        goto done;
    have_ps = 1;
    if (ax.ndim != 2 || !has_format(&ax, 2, "h") || pv.ndim != 1 || !has_format(&pv, 4, "f") ||
        ps.ndim != 1 || !has_format(&ps, 4, "f")) {
        PyErr_SetString(PyExc_TypeError,
                        "rank_sides: a 2-D int16 ax3 and two 1-D float32 profiles");
        goto done;
    }
    for (; held < n_groups; held++)
        if (!int64_column_buffer(items[held], &gb[held]))
            goto done;
    const Py_ssize_t h = ax.shape[0], w = ax.shape[1];
    const Py_ssize_t rows = rb - 1; /* rows 0..rb-2, read from the bottom up */
    const Py_ssize_t many = 3 * keep;
    if (rows < 1 || rows > h) { /* (numpy's first_gap of no rows is an error) */
        Py_INCREF(Py_None);
        result = Py_None;
        goto done;
    }
    Py_ssize_t total = 0;
    for (Py_ssize_t g = 0; g < n_groups; g++)
        total += gb[g].shape[0] < many ? gb[g].shape[0] : many;
    const size_t slots = (size_t)(total > 0 ? total : 1);
    best = PyMem_Malloc((size_t)(many + 1) * sizeof *best);
    cols = PyMem_Malloc(slots * sizeof *cols);
    run = PyMem_Malloc(slots * sizeof *run);
    late = PyMem_Malloc(slots * sizeof *late);
    rank = PyMem_Malloc(slots * sizeof *rank);
    starts = PyMem_Malloc((size_t)(n_groups + 1) * sizeof *starts);
    if (best == NULL || cols == NULL || run == NULL || late == NULL || rank == NULL ||
        starts == NULL) {
        PyErr_NoMemory();
        goto done;
    }
#define PROF(b, c) (*(const float *)((const char *)(b).buf + (c) * (b).strides[0]))
    /* each group's 3 * keep strongest columns, strongest first */
    Py_ssize_t n = 0;
    for (Py_ssize_t g = 0; g < n_groups; g++) {
        starts[g] = n;
        Py_ssize_t len = 0;
        for (Py_ssize_t i = 0; i < gb[g].shape[0]; i++) {
            long long c = *(const long long *)((const char *)gb[g].buf + i * gb[g].strides[0]);
            if (c < 0 || c >= w || c >= pv.shape[0] || c >= ps.shape[0])
                goto numpy;
            /* a NaN orders unlike numpy's sort (it never compares less) */
            if (isnan(PROF(pv, (Py_ssize_t)c)) || isnan(PROF(ps, (Py_ssize_t)c)))
                goto numpy;
            rank_insert(best, &len, many, (double)PROF(pv, (Py_ssize_t)c), (Py_ssize_t)c);
        }
        /* a tie within the 3 * keep only orders them (the ranks below decide, where they
         * differ); one across the last place decides which are taken */
        if (rank_tied(best, len, many - 1, many))
            goto numpy;
        for (Py_ssize_t p = 0; p < len && p < many; p++)
            cols[n++] = best[p].at;
    }
    starts[n_groups] = n;
    /* edge runs up from the floor-contact row (profiles.first_gap, profiles.late_run) */
    int any_late = 0;
    for (Py_ssize_t j = 0; j < n; j++) {
        const Py_ssize_t c = cols[j];
        const float a = 0.25f * PROF(ps, c);
        const float m = a < (float)cap ? a : (float)cap;
        const float t = m > (float)low ? m : (float)low;
        if (!(t > -32768.0f && t < 32767.0f))
            goto numpy; /* (numpy's int16 cast of such a threshold is no value to match) */
        const int thr = (int)(short)floorf(t);
        const char *col = (const char *)ax.buf + c * ax.strides[1];
#define ON(i) (*(const short *)(col + (rb - 2 - (i)) * ax.strides[0]) > thr)
        Py_ssize_t len = rows;
        if (rows > 2) {
            for (Py_ssize_t i = 0; i + 2 < rows; i++)
                if (!ON(i) && !ON(i + 1) && !ON(i + 2)) {
                    len = i;
                    break;
                }
        } else {
            for (Py_ssize_t i = 0; i < rows; i++)
                if (!ON(i)) {
                    len = i;
                    break;
                }
        }
        Py_ssize_t lr = 0;
        if (len < 3 && rows >= 6 && late_rows >= 1) {
            Py_ssize_t start = -1;
            for (Py_ssize_t i = 0; i + 2 < rows && i < late_rows; i++)
                if (ON(i) && ON(i + 1) && ON(i + 2)) {
                    start = i;
                    break;
                }
            if (start >= 0) {
                Py_ssize_t end = rows;
                for (Py_ssize_t i = start; i + 2 < rows; i++)
                    if (!ON(i) && !ON(i + 1) && !ON(i + 2)) {
                        end = i;
                        break;
                    }
                lr = end - start;
            }
        }
#undef ON
        run[j] = len;
        late[j] = lr;
        any_late |= lr >= 3;
        rank[j] = (double)PROF(pv, c) * sqrt((double)(len > 1 ? len : 1));
    }
    if (any_late) {
        /* runs that start higher up rank below every run from the floor */
        double top = 0.0;
        for (Py_ssize_t j = 0; j < n; j++) {
            double lrank = (double)PROF(pv, cols[j]) * sqrt((double)(late[j] > 1 ? late[j] : 1));
            if (j == 0 || lrank > top)
                top = lrank;
        }
        const double below_all = top + 1.0;
        for (Py_ssize_t j = 0; j < n; j++)
            if (late[j] >= 3) {
                rank[j] = (double)PROF(pv, cols[j]) * sqrt((double)late[j]) - below_all;
                run[j] = late[j];
            }
    }
#undef PROF
    result = PyList_New(n_groups);
    if (result == NULL)
        goto done;
    for (Py_ssize_t g = 0; g < n_groups; g++) {
        Py_ssize_t len = 0;
        for (Py_ssize_t j = starts[g]; j < starts[g + 1]; j++)
            if (run[j] >= 3)
                rank_insert(best, &len, keep, rank[j], cols[j]);
        if (rank_tied(best, len, 0, keep)) {
            Py_CLEAR(result);
            goto numpy;
        }
        const Py_ssize_t k = len < keep ? len : keep;
        PyObject *list = PyList_New(k);
        if (list == NULL) {
            Py_CLEAR(result);
            goto done;
        }
        PyList_SET_ITEM(result, g, list);
        for (Py_ssize_t p = 0; p < k; p++) {
            PyObject *c = PyLong_FromSsize_t(best[p].at);
            if (c == NULL) {
                Py_CLEAR(result);
                goto done;
            }
            PyList_SET_ITEM(list, p, c);
        }
    }
    goto done;
numpy:
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyMem_Free(best);
    PyMem_Free(cols);
    PyMem_Free(run);
    PyMem_Free(late);
    PyMem_Free(rank);
    PyMem_Free(starts);
    for (Py_ssize_t g = 0; g < held; g++)
        PyBuffer_Release(&gb[g]);
    PyMem_Free(gb);
    if (have_ps)
        PyBuffer_Release(&ps);
    if (have_pv)
        PyBuffer_Release(&pv);
    if (have_ax)
        PyBuffer_Release(&ax);
    Py_DECREF(groups);
    return result;
}

/* A C-contiguous writable output of ``rows`` x ``cols`` items of ``itemsize`` bytes in
 * one of ``formats``; 0 with an error set if it is none. */
static int table_out(PyObject *obj, Py_buffer *b, Py_ssize_t rows, Py_ssize_t cols,
                     Py_ssize_t itemsize, const char *formats)
{
    if (PyObject_GetBuffer(obj, b, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0)
        return 0;
    if (b->ndim != 2 || b->shape[0] != rows || b->shape[1] != cols ||
        !has_format(b, itemsize, formats)) {
        PyBuffer_Release(b);
        PyErr_SetString(PyExc_TypeError, "side_tables: an output of the wrong shape or type");
        return 0;
    }
    return 1;
}

/* side_tables(ax3, cols, thresholds, rb, counts, below, nxt, csum): search.Sides' tables
 * in one pass, or None (the caller builds them in numpy) where a threshold is no int16
 * value once floored, a column falls outside ax3 (int16, 2-D) or rb outside 1..its rows.
 * For the k side columns, then each one's column 4 to its left and 4 to its right (clamped
 * to the frame), the rows 0..rb-1 whose gradient exceeds floor(threshold) (float64, one a
 * side column, numpy's cast to int16): counts (int32, rb + 1 x 3k + 1) the edge rows above
 * each row (profiles.running_counts, a last column of zeros), below (int32, rb x k) those
 * in r..rb-1, nxt (int64, rb x k) the first edge row at or below each row, rb if none
 * (profiles.next_true), csum (float64, rb + 1 x k) the side column's gradient summed
 * above each row (whole numbers: exact, as cv2.integral's); returns run_top, per side
 * column the top row of its edge run up from row rb - 1 (gaps under 3 rows), a list. */
static PyObject *side_tables(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *ax_obj, *cols_obj, *thr_obj, *counts_obj, *below_obj, *nxt_obj, *csum_obj;
    Py_ssize_t rb;
    if (!PyArg_ParseTuple(args, "OOOnOOOO:side_tables", &ax_obj, &cols_obj, &thr_obj, &rb,
                          &counts_obj, &below_obj, &nxt_obj, &csum_obj))
        return NULL;
    PyObject *cols = PySequence_Fast(cols_obj, "side_tables: cols must be a sequence");
    if (cols == NULL)
        return NULL;
    const Py_ssize_t k = PySequence_Fast_GET_SIZE(cols);
    PyObject **items = PySequence_Fast_ITEMS(cols);
    Py_buffer ax, thr, counts, below, nxt, csum;
    int have = 0; /* buffers acquired, in the order above */
    PyObject *result = NULL;
    Py_ssize_t *at = NULL;
    int *limit = NULL;
    if (PyObject_GetBuffer(ax_obj, &ax, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        goto done;
    have = 1;
    if (PyObject_GetBuffer(thr_obj, &thr, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        goto done;
    have = 2;
    if (ax.ndim != 2 || !has_format(&ax, 2, "h") || thr.ndim != 1 || !has_format(&thr, 8, "d") ||
        thr.shape[0] != k) {
        PyErr_SetString(PyExc_TypeError,
                        "side_tables: a 2-D int16 ax3 and one float64 threshold a column");
        goto done;
    }
    if (!table_out(counts_obj, &counts, rb + 1, 3 * k + 1, 4, "il"))
        goto done;
    have = 3;
    if (!table_out(below_obj, &below, rb, k, 4, "il"))
        goto done;
    have = 4;
    if (!table_out(nxt_obj, &nxt, rb, k, 8, "lq"))
        goto done;
    have = 5;
    if (!table_out(csum_obj, &csum, rb + 1, k, 8, "d"))
        goto done;
    have = 6;
    const Py_ssize_t h = ax.shape[0], w = ax.shape[1];
    if (rb < 1 || rb > h || k < 1)
        goto numpy;
    at = PyMem_Malloc((size_t)(3 * k) * sizeof *at);
    limit = PyMem_Malloc((size_t)k * sizeof *limit);
    if (at == NULL || limit == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    for (Py_ssize_t j = 0; j < k; j++) {
        Py_ssize_t c = PyNumber_AsSsize_t(items[j], PyExc_OverflowError);
        if (c == -1 && PyErr_Occurred())
            goto done;
        if (c < 0 || c >= w)
            goto numpy;
        at[j] = c;
        at[k + j] = c - 4 > 0 ? c - 4 : 0;
        at[2 * k + j] = c + 4 < w - 1 ? c + 4 : w - 1;
        const double t = floor(*(const double *)((const char *)thr.buf + j * thr.strides[0]));
        if (!(t >= -32768.0 && t <= 32767.0))
            goto numpy;
        limit[j] = (int)t;
    }
    {
        const Py_ssize_t width = 3 * k + 1;
        int *cnt = (int *)counts.buf;
        int *bel = (int *)below.buf;
        long long *next = (long long *)nxt.buf;
        double *sum = (double *)csum.buf;
        const char *base = (const char *)ax.buf;
#define AX(r, j) (*(const short *)(base + (r) * ax.strides[0] + at[j] * ax.strides[1]))
        for (Py_ssize_t j = 0; j < width; j++)
            cnt[j] = 0;
        for (Py_ssize_t j = 0; j < k; j++)
            sum[j] = 0.0;
        for (Py_ssize_t r = 0; r < rb; r++) {
            int *prev = cnt + r * width, *row = prev + width;
            for (Py_ssize_t j = 0; j < 3 * k; j++)
                row[j] = prev[j] + (AX(r, j) > limit[j % k]);
            row[3 * k] = 0;
            for (Py_ssize_t j = 0; j < k; j++)
                sum[(r + 1) * k + j] = sum[r * k + j] + (double)AX(r, j);
        }
        const int *last = cnt + rb * width;
        for (Py_ssize_t r = 0; r < rb; r++)
            for (Py_ssize_t j = 0; j < k; j++)
                bel[r * k + j] = last[j] - cnt[r * width + j];
        for (Py_ssize_t j = 0; j < k; j++) {
            long long low = (long long)rb;
            for (Py_ssize_t r = rb - 1; r >= 0; r--) {
                if (AX(r, j) > limit[j])
                    low = (long long)r;
                next[r * k + j] = low;
            }
        }
        result = PyList_New(k);
        if (result == NULL)
            goto done;
        for (Py_ssize_t j = 0; j < k; j++) {
            /* up from row rb - 2 (row rb - 1 left out, as the numpy path's on[:rb - 1]) */
            Py_ssize_t top = rb - 1;
            if (rb - 1 >= 3) {
                const Py_ssize_t n = rb - 1;
                Py_ssize_t gap = n;
                for (Py_ssize_t i = 0; i + 2 < n; i++)
                    if (!(AX(n - 1 - i, j) > limit[j]) && !(AX(n - 2 - i, j) > limit[j]) &&
                        !(AX(n - 3 - i, j) > limit[j])) {
                        gap = i;
                        break;
                    }
                top = rb - 1 - gap;
            }
#undef AX
            PyObject *v = PyLong_FromSsize_t(top);
            if (v == NULL) {
                Py_CLEAR(result);
                goto done;
            }
            PyList_SET_ITEM(result, j, v);
        }
    }
    goto done;
numpy:
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyMem_Free(at);
    PyMem_Free(limit);
    if (have >= 6)
        PyBuffer_Release(&csum);
    if (have >= 5)
        PyBuffer_Release(&nxt);
    if (have >= 4)
        PyBuffer_Release(&below);
    if (have >= 3)
        PyBuffer_Release(&counts);
    if (have >= 2)
        PyBuffer_Release(&thr);
    if (have >= 1)
        PyBuffer_Release(&ax);
    Py_DECREF(cols);
    return result;
}

/* The float32 mean of column x of an 8-bit strip as numpy's mean: the (whole, exact) sum
 * divided in float64 by the row count (numpy divides by an intp count), then rounded. */
static float column_mean(const char *base, Py_ssize_t rows, Py_ssize_t rs, Py_ssize_t cs,
                         Py_ssize_t x)
{
    long sum = 0;
    for (Py_ssize_t r = 0; r < rows; r++)
        sum += (unsigned char)base[r * rs + x * cs];
    return (float)((double)sum / (double)rows);
}

/* The median of three floats (numpy's sort's middle value: no NaNs here). */
static float middle3(float a, float b, float c)
{
    float lo = a < b ? a : b, hi = a < b ? b : a;
    return c < lo ? lo : (c > hi ? hi : c);
}

/* line_columns(strip, cols, beside, contrast, same, same_max): search.line_columns' columns
 * (a list, in the order of cols; the caller makes it a set). The strip's (uint8, 2-D,
 * rows >= 1) column means in float32 as numpy's mean (whole sums, divided in float64 and
 * rounded to float32); per column c with c - beside - 2 >= 0 and c + beside + 3 <= w, the
 * medians of three of the means at c - beside - 2..c - beside and c + beside..c + beside
 * + 2, their middle (float64, rounded to float32), the largest float32 |mean - middle|
 * over c - beside + 2..c + beside - 2 (beside >= 2), kept where that contrast >=
 * ``contrast`` and the two medians differ by at most min(same * contrast, same_max),
 * in float64 as numpy. Columns whose window leaves the strip are skipped, as numpy's. */
static PyObject *line_columns(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *strip_obj, *cols_obj;
    Py_ssize_t d;
    double contrast_min, same, same_max;
    if (!PyArg_ParseTuple(args, "OOnddd:line_columns", &strip_obj, &cols_obj, &d, &contrast_min,
                          &same, &same_max))
        return NULL;
    PyObject *cols = PySequence_Fast(cols_obj, "line_columns: cols must be a sequence");
    if (cols == NULL)
        return NULL;
    Py_buffer strip;
    if (PyObject_GetBuffer(strip_obj, &strip, PyBUF_STRIDES | PyBUF_FORMAT) < 0) {
        Py_DECREF(cols);
        return NULL;
    }
    PyObject *result = NULL;
    float *mean = NULL;
    unsigned char *known = NULL;
    if (strip.ndim != 2 || !is_u8(&strip) || strip.shape[0] < 1 || d < 2) {
        PyErr_SetString(PyExc_TypeError,
                        "line_columns: a 2-D uint8 strip of one row or more, beside >= 2");
        goto done;
    }
    const Py_ssize_t rows = strip.shape[0], w = strip.shape[1];
    const Py_ssize_t rs = strip.strides[0], cs = strip.strides[1];
    const char *base = (const char *)strip.buf;
    const Py_ssize_t n_cols = PySequence_Fast_GET_SIZE(cols);
    PyObject **items = PySequence_Fast_ITEMS(cols);
    mean = PyMem_Malloc((size_t)(w > 0 ? w : 1) * sizeof *mean);
    known = PyMem_Calloc((size_t)(w > 0 ? w : 1), 1);
    if (mean == NULL || known == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    result = PyList_New(0);
    if (result == NULL)
        goto done;
/* the float32 mean of column x, computed on first use */
#define MEAN(x) (known[x] ? mean[x] : (known[x] = 1, mean[x] = column_mean(base, rows, rs, cs, (x))))
    for (Py_ssize_t i = 0; i < n_cols; i++) {
        Py_ssize_t c = PyNumber_AsSsize_t(items[i], PyExc_OverflowError);
        if (c == -1 && PyErr_Occurred())
            goto fail;
        if (c - d - 2 < 0 || c + d + 3 > w)
            continue;
        const double left = (double)middle3(MEAN(c - d - 2), MEAN(c - d - 1), MEAN(c - d));
        const double right = (double)middle3(MEAN(c + d), MEAN(c + d + 1), MEAN(c + d + 2));
        const float mid = (float)(0.5 * (left + right));
        float top = 0.0f;
        for (Py_ssize_t x = c - d + 2; x <= c + d - 2; x++) {
            const float diff = fabsf(MEAN(x) - mid);
            if (x == c - d + 2 || diff > top)
                top = diff;
        }
        const double contrast = (double)top;
        const double apart = fabs(left - right);
        const double most = same * contrast < same_max ? same * contrast : same_max;
        if (!(contrast >= contrast_min && apart <= most))
            continue;
        PyObject *v = PyLong_FromSsize_t(c);
        if (v == NULL || PyList_Append(result, v) < 0) {
            Py_XDECREF(v);
            goto fail;
        }
        Py_DECREF(v);
    }
#undef MEAN
    goto done;
fail:
    Py_CLEAR(result);
done:
    PyMem_Free(mean);
    PyMem_Free(known);
    PyBuffer_Release(&strip);
    Py_DECREF(cols);
    return result;
}

/* The k-th smallest (0-based) of v[0..n-1], NaN-free, by quickselect (v is reordered:
 * every entry before k is <= v[k]). Order statistics are values, whatever the selection
 * (numpy's sort gives the same ones), so long as no two entries are equal but told apart
 * (signed zeros: the callers leave such lanes to numpy). */
static int float_order(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static float select_kth(float *v, Py_ssize_t n, Py_ssize_t k)
{
    Py_ssize_t lo = 0, hi = n - 1;
    /* partitions allowed before the stretch left is sorted whole: about 2 log2(n), so an
     * input built against the median of three stays O(n log n), as numpy's sort */
    int budget = 2;
    for (Py_ssize_t m = n; m > 1; m >>= 1)
        budget += 2;
    while (hi - lo > 16) {
        if (budget-- == 0) {
            qsort(v + lo, (size_t)(hi - lo + 1), sizeof *v, float_order);
            return v[k];
        }
        /* the median of three as the pivot, then Hoare's partition */
        Py_ssize_t mid = lo + (hi - lo) / 2;
        float a = v[lo], b = v[mid], c = v[hi];
        float p = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
        Py_ssize_t i = lo, j = hi;
        while (i <= j) {
            while (v[i] < p)
                i++;
            while (p < v[j])
                j--;
            if (i <= j) {
                float t = v[i];
                v[i] = v[j];
                v[j] = t;
                i++;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return v[k]; /* between the two parts: entries equal to the pivot */
    }
    for (Py_ssize_t i = lo + 1; i <= hi; i++) { /* a short stretch: insertion sort */
        float t = v[i];
        Py_ssize_t j = i - 1;
        while (j >= lo && t < v[j]) {
            v[j + 1] = v[j];
            j--;
        }
        v[j + 1] = t;
    }
    return v[k];
}

/* median_float32(src, axis, out): profiles.median_of of a float32 array of 1 or 2
 * dimensions (any strides) along ``axis`` (its lanes: at least one value each) into out
 * (C-contiguous float32, one entry per lane): the middle value of an odd count, the two
 * middle ones averaged in float32 ((a + b) / 2, as np.median) for an even one. Returns
 * False (out unspecified) when a lane holds a NaN or a negative zero (numpy's sort places
 * those; the caller sorts then), else True. One call for numpy's copy, sort and picks:
 * the stages take ~70 medians of short float lanes a frame. */
static PyObject *median_float32(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *src_obj, *out_obj;
    int axis;
    if (!PyArg_ParseTuple(args, "OiO:median_float32", &src_obj, &axis, &out_obj))
        return NULL;
    Py_buffer src, out;
    if (PyObject_GetBuffer(src_obj, &src, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) <
        0) {
        PyBuffer_Release(&src);
        return NULL;
    }
    PyObject *result = NULL;
    float *buf = NULL;
    const int nd = src.ndim;
    if (src.format == NULL || strcmp(src.format, "f") != 0 || src.itemsize != 4 ||
        out.format == NULL || strcmp(out.format, "f") != 0 || out.itemsize != 4) {
        PyErr_SetString(PyExc_TypeError, "median_float32: float32 source and output");
        goto done;
    }
    if (nd < 1 || nd > 2 || axis < 0 || axis >= nd || src.shape[axis] < 1) {
        PyErr_SetString(PyExc_ValueError, "median_float32: 1-D or 2-D, lanes of a value or more");
        goto done;
    }
    const Py_ssize_t n = src.shape[axis];
    const Py_ssize_t lanes = nd == 1 ? 1 : src.shape[1 - axis];
    const Py_ssize_t along = src.strides[axis];
    const Py_ssize_t across = nd == 1 ? 0 : src.strides[1 - axis];
    if (out.len != lanes * 4) {
        PyErr_SetString(PyExc_ValueError, "median_float32: one output entry per lane");
        goto done;
    }
    buf = PyMem_Malloc((size_t)(n > 0 ? n : 1) * sizeof *buf);
    if (buf == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    float *o = (float *)out.buf;
    const Py_ssize_t k = n / 2;
    int plain = 1;
    for (Py_ssize_t lane = 0; lane < lanes && plain; lane++) {
        const char *p = (const char *)src.buf + lane * across;
        for (Py_ssize_t i = 0; i < n; i++) {
            float v = *(const float *)(p + i * along);
            if (v != v || (v == 0.0f && signbit(v))) {
                plain = 0; /* a NaN or a -0: numpy's sort decides its place */
                break;
            }
            buf[i] = v;
        }
        if (!plain)
            break;
        float upper = select_kth(buf, n, k);
        if (n % 2) {
            o[lane] = upper;
        } else {
            float lower = buf[0]; /* the largest entry before k */
            for (Py_ssize_t i = 1; i < k; i++)
                lower = buf[i] > lower ? buf[i] : lower;
            float sum = lower + upper;
            o[lane] = sum / 2.0f;
        }
    }
    result = PyBool_FromLong(plain);
done:
    PyMem_Free(buf);
    PyBuffer_Release(&out);
    PyBuffer_Release(&src);
    return result;
}

/* lines_on_rows(x, b, a, e, edge_min, contrast, out): extent._lines_on_rows' flags for the
 * n = len(x) - 2b rows of the float32 |d/dy| block x (rows r - b .. r + b of each row r,
 * any strides; no NaN) into out (C-contiguous n x columns bool): per entry, the largest of
 * the 2e + 1 rows round the row at least float32(edge_min) and at least float32(contrast)
 * times the smaller of the means of the rows b..a above and a..b below (each a float32 sum
 * added from the nearest-first row's far end as the numpy loop adds them, divided by the
 * count in float32). ~7 calls a frame of a dozen numpy passes each. */
static PyObject *lines_on_rows(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *x_obj, *out_obj;
    Py_ssize_t b, a, e;
    double edge_min_d, contrast_d;
    if (!PyArg_ParseTuple(args, "OnnnddO:lines_on_rows", &x_obj, &b, &a, &e, &edge_min_d,
                          &contrast_d, &out_obj))
        return NULL;
    Py_buffer x, out;
    if (PyObject_GetBuffer(x_obj, &x, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) <
        0) {
        PyBuffer_Release(&x);
        return NULL;
    }
    PyObject *result = NULL;
    if (x.ndim != 2 || x.format == NULL || strcmp(x.format, "f") != 0 || x.itemsize != 4 ||
        out.itemsize != 1 || out.format == NULL || strcmp(out.format, "?") != 0) {
        PyErr_SetString(PyExc_TypeError, "lines_on_rows: a 2-D float32 block, bool flags");
        goto done;
    }
    if (a < 0 || b < a || e < 0 || e > b || x.shape[0] < 2 * b) {
        PyErr_SetString(PyExc_ValueError, "lines_on_rows: 0 <= a <= b, e <= b, 2b rows or more");
        goto done;
    }
    const Py_ssize_t n = x.shape[0] - 2 * b, w = x.shape[1];
    if (out.len != n * w) {
        PyErr_SetString(PyExc_ValueError, "lines_on_rows: one flag per row and column");
        goto done;
    }
    const float edge_min = (float)edge_min_d, contrast = (float)contrast_d;
    const float count = (float)(b - a + 1);
    const Py_ssize_t rs = x.strides[0], cs = x.strides[1];
    const char *base = (const char *)x.buf;
    unsigned char *o = (unsigned char *)out.buf;
    if (cs == (Py_ssize_t)sizeof(float) && b - a <= 15 && e <= 15) {
        /* packed rows: per output row, the column loop innermost over row pointers (gcc
         * vectorises it; each entry's sums and maxima in the same order as below) */
        for (Py_ssize_t r = 0; r < n; r++) {
            const float *restrict rows_e[31], *restrict rows_a[16], *restrict rows_b[16];
            for (Py_ssize_t k = 0; k <= 2 * e; k++)
                rows_e[k] = (const float *)(base + (r + b - e + k) * rs);
            for (Py_ssize_t k = 0; k <= b - a; k++) {
                rows_a[k] = (const float *)(base + (r + k) * rs);
                rows_b[k] = (const float *)(base + (r + b + a + k) * rs);
            }
            unsigned char *restrict orow = o + r * w;
            for (Py_ssize_t c = 0; c < w; c++) {
                float edge = rows_e[0][c];
                for (Py_ssize_t k = 1; k <= 2 * e; k++) {
                    float v = rows_e[k][c];
                    edge = v > edge ? v : edge;
                }
                float above = rows_a[0][c], below = rows_b[0][c];
                for (Py_ssize_t k = 1; k <= b - a; k++) {
                    above = above + rows_a[k][c];
                    below = below + rows_b[k][c];
                }
                above = above / count;
                below = below / count;
                float low = below < above ? below : above;
                float scaled = contrast * low;
                orow[c] = edge >= edge_min && edge >= scaled;
            }
        }
        Py_INCREF(Py_None);
        result = Py_None;
        goto done;
    }
#define AT(r, c) (*(const float *)(base + (r) * rs + (c) * cs))
    for (Py_ssize_t r = 0; r < n; r++) {
        for (Py_ssize_t c = 0; c < w; c++) {
            float edge = AT(r + b - e, c);
            for (Py_ssize_t k = 1; k <= 2 * e; k++) {
                float v = AT(r + b - e + k, c);
                edge = v > edge ? v : edge;
            }
            float above = AT(r, c), below = AT(r + b + a, c);
            for (Py_ssize_t k = 1; k <= b - a; k++) {
                above = above + AT(r + k, c);
                below = below + AT(r + b + a + k, c);
            }
            above = above / count;
            below = below / count;
            float low = below < above ? below : above;
            float scaled = contrast * low;
            o[r * w + c] = edge >= edge_min && edge >= scaled;
        }
    }
#undef AT
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyBuffer_Release(&out);
    PyBuffer_Release(&x);
    return result;
}

/* The float32 norm of (x, y), as row_norms takes it: the squares added from the left. */
static float norm2f(float x, float y)
{
    float acc = x * x;
    float sq = y * y;
    acc = acc + sq;
    return sqrtf(acc);
}

/* region.shadow_columns of one colour (l, a, b) over one floor colour (fl, fa, fb), in
 * float32 step by step as numpy takes it. */
static int shadow_of(float l, float a, float b, float fl, float fa, float fb, float darker,
                     float chroma, float floor_chroma)
{
    float k = l / (fl > 1.0f ? fl : 1.0f);
    float fa0 = fa - 128.0f, fb0 = fb - 128.0f;
    float ka = k * fa0, kb = k * fb0;
    float off = norm2f((a - 128.0f) - ka, (b - 128.0f) - kb);
    int hued = norm2f(fa0, fb0) >= floor_chroma;
    return (fl - l >= darker) && (off <= chroma) && hued;
}

/* floor_chroma(foot, floor, ref, near_share, far, chroma, face_step, shadow, darker,
 * floor_chroma_min, out): region.floor_chroma's flags (with region.shadow_columns' where
 * ``shadow``) for the W x 3 float32 Lab colours foot and floor (any strides) and the
 * face's float32 colour ref (3 values, any stride) into out (W bools, contiguous); the
 * thresholds taken to float32 as numpy compares Python floats with float32 arrays. Every
 * step in float32 in numpy's order (ISO C99: no FMA), so the same flags. Three calls a
 * frame of two dozen numpy passes each. */
static PyObject *floor_chroma(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *foot_obj, *floor_obj, *ref_obj, *out_obj;
    double near_share_d, far_d, chroma_d, face_step_d, darker_d, floor_chroma_d;
    int shadow;
    if (!PyArg_ParseTuple(args, "OOOddddpddO:floor_chroma", &foot_obj, &floor_obj, &ref_obj,
                          &near_share_d, &far_d, &chroma_d, &face_step_d, &shadow, &darker_d,
                          &floor_chroma_d, &out_obj))
        return NULL;
    Py_buffer foot, floor, ref, out;
    if (PyObject_GetBuffer(foot_obj, &foot, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(floor_obj, &floor, PyBUF_STRIDES | PyBUF_FORMAT) < 0) {
        PyBuffer_Release(&foot);
        return NULL;
    }
    if (PyObject_GetBuffer(ref_obj, &ref, PyBUF_STRIDES | PyBUF_FORMAT) < 0) {
        PyBuffer_Release(&floor);
        PyBuffer_Release(&foot);
        return NULL;
    }
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) <
        0) {
        PyBuffer_Release(&ref);
        PyBuffer_Release(&floor);
        PyBuffer_Release(&foot);
        return NULL;
    }
    PyObject *result = NULL;
#define IS_F32(v) ((v).format != NULL && strcmp((v).format, "f") == 0 && (v).itemsize == 4)
    if (!IS_F32(foot) || !IS_F32(floor) || !IS_F32(ref) || out.itemsize != 1 ||
        out.format == NULL || strcmp(out.format, "?") != 0) {
        PyErr_SetString(PyExc_TypeError, "floor_chroma: float32 colours, bool flags");
        goto done;
    }
#undef IS_F32
    if (foot.ndim != 2 || floor.ndim != 2 || foot.shape[1] != 3 || floor.shape[1] != 3 ||
        foot.shape[0] != floor.shape[0] || ref.ndim != 1 || ref.shape[0] != 3 ||
        out.len != foot.shape[0]) {
        PyErr_SetString(PyExc_ValueError, "floor_chroma: W x 3 foot and floor, 3 ref, W flags");
        goto done;
    }
    const float near_share = (float)near_share_d, far = (float)far_d, chroma = (float)chroma_d;
    const float face_step = (float)face_step_d, darker = (float)darker_d;
    const float floor_chroma_min = (float)floor_chroma_d;
    const char *rp = (const char *)ref.buf;
    const float rl = *(const float *)rp, ra = *(const float *)(rp + ref.strides[0]),
                rb = *(const float *)(rp + 2 * ref.strides[0]);
    unsigned char *o = (unsigned char *)out.buf;
    for (Py_ssize_t c = 0; c < foot.shape[0]; c++) {
        const char *p = (const char *)foot.buf + c * foot.strides[0];
        const char *q = (const char *)floor.buf + c * floor.strides[0];
        const float l = *(const float *)p, a = *(const float *)(p + foot.strides[1]),
                    b = *(const float *)(p + 2 * foot.strides[1]);
        const float fl = *(const float *)q, fa = *(const float *)(q + floor.strides[1]),
                    fb = *(const float *)(q + 2 * floor.strides[1]);
        const float foot_step = norm2f(a - fa, b - fb);
        const float face_floor = norm2f(ra - fa, rb - fb);
        const float to_face = near_share * norm2f(a - ra, b - rb);
        const int near = foot_step < to_face && foot_step < far;
        int on = (foot_step < chroma || near) && face_floor >= face_step;
        if (shadow && !on)
            on = shadow_of(l, a, b, fl, fa, fb, darker, chroma, floor_chroma_min) &&
                 !shadow_of(rl, ra, rb, fl, fa, fb, darker, chroma, floor_chroma_min);
        o[c] = (unsigned char)on;
    }
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyBuffer_Release(&out);
    PyBuffer_Release(&ref);
    PyBuffer_Release(&floor);
    PyBuffer_Release(&foot);
    return result;
}

/* The float32 median of the 8-bit values v[0], v[s], ... v[(n-1)s] (n of 1..16), as
 * profiles.median_u8 takes it: the middle one, or the two middle ones averaged in float32. */
#define CE6(a, b)                                                                          \
    do {                                                                                   \
        int lo_ = t6[a] < t6[b] ? t6[a] : t6[b], hi_ = t6[a] < t6[b] ? t6[b] : t6[a];      \
        t6[a] = lo_;                                                                       \
        t6[b] = hi_;                                                                       \
    } while (0)
static float median_u8_lane(const unsigned char *v, Py_ssize_t s, int n)
{
    if (n == 6) { /* the strips' 6 columns: an optimal sorting network (12 exchanges) */
        int t6[6];
        for (int i = 0; i < 6; i++)
            t6[i] = v[i * s];
        CE6(0, 5);
        CE6(1, 3);
        CE6(2, 4);
        CE6(1, 2);
        CE6(3, 4);
        CE6(0, 3);
        CE6(2, 5);
        CE6(0, 1);
        CE6(2, 3);
        CE6(4, 5);
        CE6(1, 2);
        CE6(3, 4);
        float sum6 = (float)t6[2] + (float)t6[3];
        return sum6 / 2.0f;
    }
    unsigned char t[16];
    for (int i = 0; i < n; i++) {
        unsigned char x = v[i * s];
        int j = i - 1;
        while (j >= 0 && t[j] > x) {
            t[j + 1] = t[j];
            j--;
        }
        t[j + 1] = x;
    }
    if (n % 2)
        return (float)t[n / 2];
    float sum = (float)t[n / 2 - 1] + (float)t[n / 2];
    return sum / 2.0f;
}

/* The float32 norm of a 3-vector, as row_norms takes it. */
static float norm3f(float x, float y, float z)
{
    float acc = x * x;
    float sq = y * y;
    acc = acc + sq;
    sq = z * z;
    acc = acc + sq;
    return sqrtf(acc);
}

/* median_of of n float32 values (n >= 1, no NaN, no negative zero) as a double. */
static double median_f(float *buf, Py_ssize_t n)
{
    const Py_ssize_t k = n / 2;
    float upper = select_kth(buf, n, k);
    if (n % 2)
        return upper;
    float lower = buf[0];
    for (Py_ssize_t i = 1; i < k; i++)
        lower = buf[i] > lower ? buf[i] : lower;
    float sum = lower + upper;
    return (double)(sum / 2.0f);
}

static double clamp_d(double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* side_walk(inside, outside, k, consts, stands, held): region._sides_walk's reading of one
 * side: ``inside`` and ``outside`` (rows x columns x 3 uint8 Lab, 1-16 columns, any
 * strides) the strip just inside the side and what is beside it; ``k`` the band row of
 * the face's top (the rows from k + 2 down are the face's); ``consts`` a float64 array of
 * the rule's constants in the order region._SIDE_WALK_CONSTANTS names them. Fills
 * ``stands`` (the side parts the face from what is beside it, per row) and ``held`` (the
 * strip holds the face's colour) and returns True; False when the side's step along the
 * face is under MIN_BESIDE_STEP (the walk gives None). Every step as numpy takes it:
 * float32 medians, norms and comparisons with thresholds taken to float32, the limits'
 * products and clamps in double, the colour weights' hypotenuses by the C library's
 * hypot (correctly rounded here: the same as Python's on these quarter-unit colours). */
static PyObject *side_walk(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *in_obj, *out_obj, *c_obj, *st_obj, *hd_obj;
    Py_ssize_t k;
    if (!PyArg_ParseTuple(args, "OOnOOO:side_walk", &in_obj, &out_obj, &k, &c_obj, &st_obj,
                          &hd_obj))
        return NULL;
    Py_buffer in, ou, cs, st, hd;
    int got = 0;
    PyObject *result = NULL;
    float *work = NULL;
    if (PyObject_GetBuffer(in_obj, &in, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        return NULL;
    got = 1;
    if (PyObject_GetBuffer(out_obj, &ou, PyBUF_STRIDES | PyBUF_FORMAT) < 0)
        goto release;
    got = 2;
    if (PyObject_GetBuffer(c_obj, &cs, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0)
        goto release;
    got = 3;
    if (PyObject_GetBuffer(st_obj, &st, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0)
        goto release;
    got = 4;
    if (PyObject_GetBuffer(hd_obj, &hd, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0)
        goto release;
    got = 5;
    if (!is_u8(&in) || !is_u8(&ou) || in.ndim != 3 || ou.ndim != 3 || in.shape[2] != 3 ||
        ou.shape[2] != 3 || in.shape[0] != ou.shape[0] || in.shape[1] < 1 ||
        in.shape[1] > 16 || ou.shape[1] < 1 || ou.shape[1] > 16) {
        PyErr_SetString(PyExc_ValueError, "side_walk: rows x 1-16 x 3 uint8 strips of one height");
        goto done;
    }
    const Py_ssize_t rows = in.shape[0];
    if (cs.format == NULL || strcmp(cs.format, "d") != 0 || cs.len != 13 * 8 || st.itemsize != 1 ||
        st.format == NULL || strcmp(st.format, "?") != 0 || hd.itemsize != 1 ||
        hd.format == NULL || strcmp(hd.format, "?") != 0 || st.len != rows || hd.len != rows) {
        PyErr_SetString(PyExc_ValueError, "side_walk: 13 float64 constants, one bool per row");
        goto done;
    }
    const double *c = (const double *)cs.buf;
    const double walk_share = c[0], min_beside = c[1], clear_step = c[2], min_top = c[3];
    const double spread = c[4], max_face = c[5], held_colour = c[6], shaded = c[7];
    const double hue_step = c[8], chromatic = c[9], hue_apart = c[10], shade_weight = c[11];
    const double drift_d = c[12];
    const Py_ssize_t drift = (Py_ssize_t)drift_d;
    const Py_ssize_t first = k + 2, m = rows - first; /* the face's rows */
    if (m < 1 || first < 0 || drift < 1 || (double)drift != drift_d) {
        PyErr_SetString(PyExc_ValueError, "side_walk: face rows below k + 2, a whole drift");
        goto done;
    }
    work = PyMem_Malloc((size_t)rows * 9 * sizeof *work);
    if (work == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    float *strip = work, *beside = work + 3 * rows, *step = work + 6 * rows;
    float *d_strip = work + 7 * rows, *tmp = work + 8 * rows;
    const int ni = (int)in.shape[1], no = (int)ou.shape[1];
    for (Py_ssize_t r = 0; r < rows; r++)
        for (int ch = 0; ch < 3; ch++) {
            strip[3 * r + ch] = median_u8_lane((const unsigned char *)in.buf + r * in.strides[0] +
                                                   ch * in.strides[2],
                                               in.strides[1], ni);
            beside[3 * r + ch] = median_u8_lane((const unsigned char *)ou.buf + r * ou.strides[0] +
                                                    ch * ou.strides[2],
                                                ou.strides[1], no);
        }
    for (Py_ssize_t r = 0; r < rows; r++)
        step[r] = norm3f(strip[3 * r] - beside[3 * r], strip[3 * r + 1] - beside[3 * r + 1],
                         strip[3 * r + 2] - beside[3 * r + 2]);
    memcpy(tmp, step + first, (size_t)m * sizeof *tmp);
    const double level = median_f(tmp, m);
    if (level < min_beside) {
        Py_INCREF(Py_False);
        result = Py_False;
        goto done;
    }
    const float stand_at = (float)clamp_d(walk_share * level, min_beside, clear_step);
    float own[3], floor_c[3];
    for (int ch = 0; ch < 3; ch++) {
        for (Py_ssize_t i = 0; i < m; i++)
            tmp[i] = strip[3 * (first + i) + ch];
        own[ch] = (float)median_f(tmp, m);
        for (Py_ssize_t i = 0; i < m; i++)
            tmp[i] = beside[3 * (first + i) + ch];
        floor_c[ch] = (float)median_f(tmp, m);
    }
    for (Py_ssize_t r = 0; r < rows; r++)
        d_strip[r] = norm3f(strip[3 * r] - own[0], strip[3 * r + 1] - own[1],
                            strip[3 * r + 2] - own[2]);
    memcpy(tmp, d_strip + first, (size_t)m * sizeof *tmp);
    const double limit = clamp_d(spread * median_f(tmp, m), min_top, max_face);
    const float limit_f = (float)limit, max_face_f = (float)max_face;
    const float min_beside_f = (float)min_beside;
    unsigned char *so = (unsigned char *)st.buf, *ho = (unsigned char *)hd.buf;
    for (Py_ssize_t r = 0; r < rows; r++) {
        int s = step[r] >= stand_at;
        if (held_colour != 0.0)
            s = s || (step[r] >= min_beside_f && d_strip[r] <= limit_f);
        so[r] = (unsigned char)s;
        float dr = 0.0f;
        if (r + drift < rows) {
            const float *a = strip + 3 * r, *b = strip + 3 * (r + drift);
            dr = norm3f((a[0] - b[0]) * 1.0f, (a[1] - b[1]) * 1.0f, (a[2] - b[2]) * 1.0f);
        }
        ho[r] = (unsigned char)(d_strip[r] <= limit_f || (d_strip[r] <= max_face_f && dr <= limit_f));
    }
    /* the face's colour weights (region._face_colour_weights), in double as Python */
    const double chroma = hypot((double)own[1] - 128.0, (double)own[2] - 128.0);
    const double apart = hypot((double)own[1] - (double)floor_c[1],
                               (double)own[2] - (double)floor_c[2]);
    const float w0 = chroma >= chromatic && apart >= hue_apart ? (float)shade_weight : 1.0f;
    if (shaded != 0.0 && (double)w0 < 1.0) {
        float *d_sh = tmp; /* reused: the shaded distances, then their face rows' copy */
        float *d_copy = beside; /* beside is read no more */
        for (Py_ssize_t r = 0; r < rows; r++)
            d_sh[r] = norm3f((strip[3 * r] - own[0]) * w0, (strip[3 * r + 1] - own[1]) * 1.0f,
                             (strip[3 * r + 2] - own[2]) * 1.0f);
        memcpy(d_copy, d_sh + first, (size_t)m * sizeof *d_copy);
        const double limit_s = clamp_d(spread * median_f(d_copy, m), min_top, max_face);
        const float limit_sf = (float)limit_s, hue_f = (float)hue_step;
        for (Py_ssize_t r = 0; r < rows; r++) {
            float dr = 0.0f;
            if (r + drift < rows) {
                const float *a = strip + 3 * r, *b = strip + 3 * (r + drift);
                dr = norm3f((a[0] - b[0]) * w0, (a[1] - b[1]) * 1.0f, (a[2] - b[2]) * 1.0f);
            }
            const int held_s = d_sh[r] <= limit_sf || (d_sh[r] <= max_face_f && dr <= limit_sf);
            const float hx = strip[3 * r + 1] - own[1], hy = strip[3 * r + 2] - own[2];
            const int hue_ok = norm2f(hx, hy) <= hue_f;
            if (held_s && hue_ok)
                ho[r] = 1;
        }
    }
    Py_INCREF(Py_True);
    result = Py_True;
done:
    PyMem_Free(work);
release:
    if (got >= 5)
        PyBuffer_Release(&hd);
    if (got >= 4)
        PyBuffer_Release(&st);
    if (got >= 3)
        PyBuffer_Release(&cs);
    if (got >= 2)
        PyBuffer_Release(&ou);
    if (got >= 1)
        PyBuffer_Release(&in);
    return got == 5 ? result : NULL;
}

static PyMethodDef methods[] = {
    {"side_walk", side_walk, METH_VARARGS,
     "side_walk(inside, outside, k, consts, stands, held): region._sides_walk's reading of a side."},
    {"floor_chroma", floor_chroma, METH_VARARGS,
     "floor_chroma(foot, floor, ref, ..., out): region.floor_chroma's flags."},
    {"median_float32", median_float32, METH_VARARGS,
     "median_float32(src, axis, out): profiles.median_of of float32 lanes (False: numpy sorts)."},
    {"lines_on_rows", lines_on_rows, METH_VARARGS,
     "lines_on_rows(x, b, a, e, edge_min, contrast, out): extent._lines_on_rows' flags."},
    {"line_columns", line_columns, METH_VARARGS,
     "line_columns(strip, cols, beside, contrast, same, same_max): search.line_columns' columns."},
    {"side_tables", side_tables, METH_VARARGS,
     "side_tables(ax3, cols, thresholds, rb, counts, below, nxt, csum): search.Sides' tables."},
    {"rank_sides", rank_sides, METH_VARARGS,
     "rank_sides(ax3, prof_v, prof_short, groups, rb, cap, low, late_rows, keep): search._rank_sides."},
    {"uncovered", uncovered, METH_VARARGS,
     "uncovered(boxes, r0, r1, c0, c1): None inside a box, else the block's uncovered pieces."},
    {"row_norms", row_norms, METH_VARARGS,
     "row_norms(x, out): the Euclidean norm of each row of 1-7 floats (profiles.row_norms)."},
    {"ramp_spans", ramp_spans, METH_VARARGS,
     "ramp_spans(strip, cols, min_cols, beside): search.ramp_columns' ramps (column, first, last)."},
    {"remap_table", remap_table, METH_VARARGS,
     "remap_table(src, stride, offsets, fx, fy, dst): OpenCV's bilinear remap by a view's table."},
    {"remap_table3", remap_table3, METH_VARARGS,
     "remap_table3(src, offsets, wtop, wbot, r0, c0, dst): remap_table's remap of a BGR block."},
    {"score_tops", score_tops, METH_VARARGS,
     "score_tops(...): scoring.score_pairs' top candidates and their features."},
    {"next_true", next_true, METH_VARARGS,
     "next_true(flags, fill, out): per entry, the first true row at or below (profiles)."},
    {"first_gap", first_gap, METH_VARARGS,
     "first_gap(on, out): per column, the first row of 3 misses (profiles.first_gap)."},
    {"walk_on", walk_on, METH_VARARGS,
     "walk_on(on, start, step, max_gap): profiles.walk_on's walk (None: walk in Python)."},
    {"middle_u8", middle_u8, METH_VARARGS,
     "middle_u8(src, network, lo, hi): the two middle values of every last-axis lane."},
    {"median_f32", median_f32, METH_VARARGS,
     "median_f32(src, axis, network, out): the float32 median of every lane along axis."},
    {"kth_counted", kth_counted, METH_VARARGS,
     "kth_counted(src, k): the k-th smallest of whole float32 values 0..1023, counted."},
    {"project3", project3, METH_VARARGS,
     "project3(src, m0, m1, m2, m3, dst): cv2.transform of a BGR image by one float32 row."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_cmiddle", "Middle order statistics of 8-bit lanes; flag walks; a table remap.", -1,
    methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__cmiddle(void)
{
    return PyModule_Create(&module);
}
