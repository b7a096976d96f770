/* The fused vision method's optional C accelerator: the two middle order statistics of
 * every lane of an 8-bit array (profiles.median_u8 takes its medians from them).
 *
 * The colour stages take a median per row, column or channel of small Lab blocks: many
 * short lanes (a few rows of a 500-column band, 6 columns of a 100-row strip), where
 * numpy's sort costs a call per lane and profiles.py's selection network a numpy call per
 * comparator. Here the same network runs over all lanes at once, in one call. Minima and
 * maxima of integers: exactly the values numpy's sort gives. Built by setup.py (optional:
 * without it, profiles.py does the same in numpy). Reads any strided buffer (numpy views).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <string.h>

/* Dimensions a source may have (numpy's own limit is 64). */
#define MAX_DIMS 64

static int is_u8(const Py_buffer *b)
{
    return b->itemsize == 1 && (b->format == NULL || strcmp(b->format, "B") == 0);
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

/* middle_u8(src, network, lo, hi): for every lane along src's last axis (uint8, any
 * strides, n values), the sorted values at n // 2 - 1 and n // 2 into lo and hi (C-contiguous
 * uint8, one entry per lane in C order of src's other axes), by the comparator network
 * given as bytes (i, j, want) per comparator: the minimum of values i and j to i (want
 * bit 0), their maximum to j (bit 1); the caller's network leaves the middles at n // 2 - 1
 * and n // 2. The lanes are gathered into n rows of all lanes, so that each comparator is
 * one pass of byte minima and maxima over contiguous rows. */
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
    unsigned char *rows = NULL;
    Py_ssize_t *offsets = NULL;
    int nd = src.ndim;
    if (!is_u8(&src) || !is_u8(&lo) || !is_u8(&hi)) {
        PyErr_SetString(PyExc_TypeError, "middle_u8: uint8 arrays only");
        goto done;
    }
    if (nd < 1 || nd > MAX_DIMS || src.shape[nd - 1] < 2 || net_len % 3 != 0) {
        PyErr_SetString(PyExc_ValueError, "middle_u8: lanes of at least two values");
        goto done;
    }
    Py_ssize_t n = src.shape[nd - 1], lanes = 1;
    for (int d = 0; d < nd - 1; d++)
        lanes *= src.shape[d];
    if (lo.len != lanes || hi.len != lanes) {
        PyErr_SetString(PyExc_ValueError, "middle_u8: one output entry per lane");
        goto done;
    }
    for (Py_ssize_t c = 0; c < net_len; c += 3) {
        if (net[c] >= n || net[c + 1] >= n || net[c] == net[c + 1] || net[c + 2] > 3) {
            PyErr_SetString(PyExc_ValueError, "middle_u8: a comparator outside the lanes");
            goto done;
        }
    }
    rows = PyMem_Malloc((size_t)(n * lanes));
    offsets = PyMem_Malloc((size_t)lanes * sizeof *offsets);
    if (rows == NULL || offsets == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    /* each lane's first value: an odometer over the other axes, last fastest (lanes next
     * to each other in memory, as a row of values, are copied a row at a time) */
    Py_ssize_t index[MAX_DIMS] = {0}, at = 0;
    int adjacent = 1;
    for (Py_ssize_t lane = 0; lane < lanes; lane++) {
        offsets[lane] = at;
        adjacent &= at == lane;
        for (int d = nd - 2; d >= 0; d--) {
            at += src.strides[d];
            if (++index[d] < src.shape[d])
                break;
            at -= src.strides[d] * src.shape[d];
            index[d] = 0;
        }
    }
    const char *base = (const char *)src.buf;
    Py_ssize_t step = src.strides[nd - 1];
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
    Py_ssize_t k = n / 2;
    memcpy(lo.buf, rows + (k - 1) * lanes, (size_t)lanes);
    memcpy(hi.buf, rows + k * lanes, (size_t)lanes);
    Py_INCREF(Py_None);
    result = Py_None;
done:
    PyMem_Free(offsets);
    PyMem_Free(rows);
    PyBuffer_Release(&hi);
    PyBuffer_Release(&lo);
    PyBuffer_Release(&src);
    return result;
}

static PyMethodDef methods[] = {
    {"middle_u8", middle_u8, METH_VARARGS,
     "middle_u8(src, network, lo, hi): the two middle values of every last-axis lane."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_cmiddle", "Middle order statistics of 8-bit lanes.", -1, methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__cmiddle(void)
{
    return PyModule_Create(&module);
}
