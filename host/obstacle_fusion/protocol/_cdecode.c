/* Optional C accelerator of obstacle_fusion.protocol.stream.StreamDecoder.
 *
 * scan(data, last_seq) walks the frames of one chunk (the decoder's pending tail and the
 * new bytes, joined) as the decoder's Python fast path does: it finds every 0x00
 * delimiter, COBS-decodes each run, checks its CRC and builds the message of every intact
 * frame of a fixed-length message it was configured with. It returns
 *
 *     (out, tail, last_seq, frames, gaps, zeros, others)
 *
 *   out       the messages in stream order; a run that is no such frame stands in its
 *             place as bytes (the run without its delimiter), for Python to decode or count
 *   tail      the bytes after the last delimiter (the start of a frame still to come)
 *   last_seq  the seq of the last intact frame before the first such run (else the
 *             last_seq given, None included)
 *   frames    intact frames built here (all of them, before and after other runs)
 *   gaps      sequence gaps up to the first other run, counted from last_seq as given
 *             (none before the first frame when it is None)
 *   zeros     runs of length 0 (a 0x00 with no frame before it)
 *   others    None when out holds no bytes; else one (index, first_seq, last_seq, gaps,
 *             count) per run left to Python: its index in out, and the intact frames
 *             between it and the next such run (count of them; gaps between them only)
 *
 * A frame is intact when its run is at most longest_run bytes long, is valid COBS (the
 * rules of the `cobs` package: no code byte 0, no code past the end, no 0x00 inside),
 * decodes to a body whose id was configured, of that id's fixed size exactly, and whose
 * CRC-16 over the whole body from that id's seed is 0 (binascii.crc_hqx: polynomial
 * 0x1021, MSB first, no final xor). A message is made as copy and pickle make one: the
 * class's tp_new, then each field set through the class's slot descriptor (configure()
 * takes only dataclasses whose __init__ does nothing else). Every index into a buffer is
 * checked against that buffer's length. A chunk of pause_frames delimiters or more is
 * scanned with the automatic garbage collection paused (as the Python path does).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdint.h>
#include <string.h>

/* The longest run this module decodes (COBS of a body of at most 254 bytes) and the
 * largest body and field count it takes. */
#define RUN_CAP 255
#define BODY_CAP 256
#define FIELD_CAP 16
#define CRC_POLY 0x1021u

typedef struct {
    PyTypeObject *type;     /* NULL: this id is left to Python */
    Py_ssize_t body_size;   /* id, seq, fields, CRC */
    uint16_t seed;          /* CRC state after the id's crc_extra byte */
    int nfields;
    char codes[FIELD_CAP];  /* struct codes: B H I b h i (little-endian) */
    PyObject *slots[FIELD_CAP]; /* the field's member descriptor */
} entry_t;

static uint16_t crc_table[256];
static entry_t entries[256];
static Py_ssize_t longest_run;  /* 0 until configure() */
static Py_ssize_t pause_frames;
static PyObject *empty_tuple;
/* Scans under way: a collection during one could run Python code that calls configure(),
 * which would pull the table from under it; configure() refuses while this is not 0. */
static int scanning;

static void make_crc_table(void)
{
    for (unsigned i = 0; i < 256; i++) {
        uint16_t crc = (uint16_t)(i << 8);
        for (int bit = 0; bit < 8; bit++) {
            crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ CRC_POLY) : (uint16_t)(crc << 1);
        }
        crc_table[i] = crc;
    }
}

static uint16_t crc16(const uint8_t *data, Py_ssize_t len, uint16_t crc)
{
    for (Py_ssize_t i = 0; i < len; i++) {
        crc = (uint16_t)((crc << 8) ^ crc_table[((crc >> 8) ^ data[i]) & 0xFFu]);
    }
    return crc;
}

/* COBS-decode src[0..len) into dst[0..cap); the decoded length, or -1 for bad COBS (or a
 * body that would not fit). */
static Py_ssize_t cobs_decode(const uint8_t *src, Py_ssize_t len, uint8_t *dst, Py_ssize_t cap)
{
    Py_ssize_t in = 0;
    Py_ssize_t out = 0;
    while (in < len) {
        unsigned code = src[in++];
        if (code == 0) {
            return -1;
        }
        Py_ssize_t copy = (Py_ssize_t)code - 1;
        if (copy > len - in || copy > cap - out) {
            return -1;
        }
        for (Py_ssize_t k = 0; k < copy; k++) {
            uint8_t byte = src[in++];
            if (byte == 0) {
                return -1;
            }
            dst[out++] = byte;
        }
        if (in >= len) {
            break;
        }
        if (code != 0xFFu) {
            if (out >= cap) {
                return -1;
            }
            dst[out++] = 0;
        }
    }
    return out;
}

static Py_ssize_t code_size(char code)
{
    switch (code) {
    case 'B': case 'b': return 1;
    case 'H': case 'h': return 2;
    case 'I': case 'i': return 4;
    default: return 0;
    }
}

/* The message of an intact body of entry e (body_size bytes, checked by the caller). */
static PyObject *build(const entry_t *e, const uint8_t *body)
{
    PyObject *msg = e->type->tp_new(e->type, empty_tuple, NULL);
    if (msg == NULL) {
        return NULL;
    }
    const uint8_t *p = body + 2;
    for (int f = 0; f < e->nfields; f++) {
        PyObject *value;
        switch (e->codes[f]) {
        case 'B':
            value = PyLong_FromLong(p[0]);
            p += 1;
            break;
        case 'b':
            value = PyLong_FromLong((int8_t)p[0]);
            p += 1;
            break;
        case 'H':
            value = PyLong_FromLong((long)((unsigned)p[0] | ((unsigned)p[1] << 8)));
            p += 2;
            break;
        case 'h':
            value = PyLong_FromLong((int16_t)(uint16_t)((unsigned)p[0] | ((unsigned)p[1] << 8)));
            p += 2;
            break;
        case 'I': {
            uint32_t v = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16)
                         | ((uint32_t)p[3] << 24);
            value = PyLong_FromUnsignedLong(v);
            p += 4;
            break;
        }
        default: { /* 'i': configure() lets no other code through */
            uint32_t v = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16)
                         | ((uint32_t)p[3] << 24);
            value = PyLong_FromLong((long)(int32_t)v);
            p += 4;
            break;
        }
        }
        if (value == NULL) {
            Py_DECREF(msg);
            return NULL;
        }
        PyObject *slot = e->slots[f];
        int failed = Py_TYPE(slot)->tp_descr_set(slot, msg, value);
        Py_DECREF(value);
        if (failed != 0) {
            Py_DECREF(msg);
            return NULL;
        }
    }
    return msg;
}

/* The intact frames after one run left to Python, up to the next one. */
typedef struct {
    Py_ssize_t index;
    unsigned first;
    unsigned last;
    Py_ssize_t gaps;
    Py_ssize_t count;
} other_t;

static int close_other(const other_t *o, PyObject **others)
{
    if (*others == NULL) {
        *others = PyList_New(0);
        if (*others == NULL) {
            return -1;
        }
    }
    PyObject *item = Py_BuildValue("(nIInn)", o->index, o->first, o->last, o->gaps, o->count);
    if (item == NULL) {
        return -1;
    }
    int failed = PyList_Append(*others, item);
    Py_DECREF(item);
    return failed;
}

static PyObject *scan_chunk(const uint8_t *data, Py_ssize_t len, PyObject *last_obj)
{
    int has_last = 0;
    unsigned last = 0;
    if (last_obj != Py_None) {
        long value = PyLong_AsLong(last_obj);
        if (value == -1 && PyErr_Occurred()) {
            return NULL;
        }
        if (value < 0 || value > 0xFF) {
            PyErr_SetString(PyExc_ValueError, "last_seq outside 0..255");
            return NULL;
        }
        has_last = 1;
        last = (unsigned)value;
    }
    /* Where the bytes after the last delimiter begin. */
    Py_ssize_t tail_at = len;
    while (tail_at > 0 && data[tail_at - 1] != 0) {
        tail_at--;
    }
    PyObject *out = PyList_New(0);
    if (out == NULL) {
        return NULL;
    }
    PyObject *others = NULL;
    PyObject *result = NULL;
    Py_ssize_t frames = 0;
    Py_ssize_t gaps = 0;
    Py_ssize_t zeros = 0;
    other_t other = {-1, 0, 0, 0, 0};  /* index -1: no run left to Python yet */

    Py_ssize_t parts = 0;
    for (Py_ssize_t at = 0; at < tail_at; parts++) {
        const uint8_t *hit = memchr(data + at, 0, (size_t)(tail_at - at));
        if (hit == NULL) {
            break;
        }
        at = (Py_ssize_t)(hit - data) + 1;
    }
    int paused = parts >= pause_frames && PyGC_IsEnabled();
    if (paused) {
        PyGC_Disable();
    }

    Py_ssize_t at = 0;
    while (at < tail_at) {
        const uint8_t *hit = memchr(data + at, 0, (size_t)(tail_at - at));
        if (hit == NULL) { /* cannot happen: data[tail_at - 1] is 0 */
            break;
        }
        const Py_ssize_t end = (Py_ssize_t)(hit - data);
        const Py_ssize_t run = end - at;
        if (run == 0) {
            zeros++;
            at = end + 1;
            continue;
        }
        const entry_t *e = NULL;
        uint8_t body[BODY_CAP];
        if (run <= longest_run && run <= RUN_CAP) {
            Py_ssize_t size = cobs_decode(data + at, run, body, BODY_CAP);
            if (size >= 1) {
                e = &entries[body[0]];
                if (e->type == NULL || size != e->body_size
                    || crc16(body, size, e->seed) != 0) {
                    e = NULL;
                }
            }
        }
        PyObject *item;
        if (e != NULL) {
            item = build(e, body);
            unsigned seq = body[1];
            if (other.index < 0) {
                if (has_last) {
                    gaps += (Py_ssize_t)((seq - last - 1u) & 0xFFu);
                }
                has_last = 1;
                last = seq;
            } else {
                if (other.count == 0) {
                    other.first = seq;
                } else {
                    other.gaps += (Py_ssize_t)((seq - other.last - 1u) & 0xFFu);
                }
                other.last = seq;
                other.count++;
            }
            frames++;
        } else {
            if (other.index >= 0 && close_other(&other, &others) != 0) {
                goto done;
            }
            other.index = PyList_GET_SIZE(out);
            other.first = other.last = 0;
            other.gaps = other.count = 0;
            item = PyBytes_FromStringAndSize((const char *)(data + at), run);
        }
        if (item == NULL) {
            goto done;
        }
        int failed = PyList_Append(out, item);
        Py_DECREF(item);
        if (failed != 0) {
            goto done;
        }
        at = end + 1;
    }
    if (other.index >= 0 && close_other(&other, &others) != 0) {
        goto done;
    }
    PyObject *tail = PyBytes_FromStringAndSize((const char *)(data + tail_at), len - tail_at);
    if (tail == NULL) {
        goto done;
    }
    PyObject *last_out = has_last ? PyLong_FromLong((long)last) : Py_NewRef(Py_None);
    if (last_out == NULL) {
        Py_DECREF(tail);
        goto done;
    }
    result = Py_BuildValue("(ONNnnnO)", out, tail, last_out, frames, gaps, zeros,
                           others != NULL ? others : Py_None);
done:
    if (paused) {
        PyGC_Enable();
    }
    Py_DECREF(out);
    Py_XDECREF(others);
    return result;
}

static PyObject *scan(PyObject *module, PyObject *const *args, Py_ssize_t nargs)
{
    (void)module;
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "scan(data, last_seq) takes 2 arguments");
        return NULL;
    }
    if (longest_run == 0) {
        PyErr_SetString(PyExc_RuntimeError, "_cdecode.configure() was not called");
        return NULL;
    }
    Py_buffer view;
    if (PyObject_GetBuffer(args[0], &view, PyBUF_SIMPLE) != 0) {
        return NULL;
    }
    scanning++;
    PyObject *result = scan_chunk((const uint8_t *)view.buf, view.len, args[1]);
    scanning--;
    PyBuffer_Release(&view);
    return result;
}

static void clear_entries(void)
{
    for (int i = 0; i < 256; i++) {
        entry_t *e = &entries[i];
        Py_CLEAR(e->type);
        for (int f = 0; f < FIELD_CAP; f++) {
            Py_CLEAR(e->slots[f]);
        }
        e->nfields = 0;
        e->body_size = 0;
        e->seed = 0;
    }
}

/* One entry from (msg_id, class, codes, slots, seed): the caller checks msg_id. */
static int configure_entry(entry_t *e, PyObject *cls, PyObject *codes, PyObject *slots,
                           unsigned long seed)
{
    if (!PyType_Check(cls) || !PyBytes_Check(codes) || !PyTuple_Check(slots)) {
        PyErr_SetString(PyExc_TypeError, "entry: (msg_id, class, bytes, tuple, seed)");
        return -1;
    }
    Py_ssize_t n = PyBytes_GET_SIZE(codes);
    if (n > FIELD_CAP || PyTuple_GET_SIZE(slots) != n || seed > 0xFFFFu) {
        PyErr_SetString(PyExc_ValueError, "entry: at most 16 fields, one slot each, 16-bit seed");
        return -1;
    }
    Py_ssize_t size = 4;
    for (Py_ssize_t f = 0; f < n; f++) {
        char code = PyBytes_AS_STRING(codes)[f];
        PyObject *slot = PyTuple_GET_ITEM(slots, f);
        if (code_size(code) == 0 || Py_TYPE(slot)->tp_descr_set == NULL) {
            PyErr_Format(PyExc_ValueError, "entry: field %zd: code %c or its slot", f, code);
            return -1;
        }
        size += code_size(code);
    }
    if (size > BODY_CAP || size - 1 > longest_run) {
        PyErr_SetString(PyExc_ValueError, "entry: body longer than the longest frame");
        return -1;
    }
    PyTypeObject *type = (PyTypeObject *)cls;
    if (type->tp_new == NULL) {
        PyErr_SetString(PyExc_TypeError, "entry: class without tp_new");
        return -1;
    }
    e->type = (PyTypeObject *)Py_NewRef(cls);
    e->nfields = (int)n;
    e->body_size = size;
    e->seed = (uint16_t)seed;
    for (Py_ssize_t f = 0; f < n; f++) {
        e->codes[f] = PyBytes_AS_STRING(codes)[f];
        e->slots[f] = Py_NewRef(PyTuple_GET_ITEM(slots, f));
    }
    return 0;
}

static PyObject *configure(PyObject *module, PyObject *args)
{
    (void)module;
    PyObject *list;
    Py_ssize_t longest;
    Py_ssize_t pause;
    if (!PyArg_ParseTuple(args, "O!nn", &PyList_Type, &list, &longest, &pause)) {
        return NULL;
    }
    if (longest < 1 || longest > RUN_CAP) {
        PyErr_Format(PyExc_ValueError, "longest run %zd outside 1..%d", longest, RUN_CAP);
        return NULL;
    }
    if (scanning != 0) {
        PyErr_SetString(PyExc_RuntimeError, "configure() during a scan");
        return NULL;
    }
    clear_entries();
    longest_run = longest;
    pause_frames = pause;
    for (Py_ssize_t i = 0; i < PyList_GET_SIZE(list); i++) {
        PyObject *item = PyList_GET_ITEM(list, i);
        unsigned int msg_id;
        PyObject *cls;
        PyObject *codes;
        PyObject *slots;
        unsigned long seed;
        if (!PyTuple_Check(item)
            || !PyArg_ParseTuple(item, "IOOOk", &msg_id, &cls, &codes, &slots, &seed)) {
            if (!PyErr_Occurred()) {
                PyErr_SetString(PyExc_TypeError, "entry: (msg_id, class, bytes, tuple, seed)");
            }
            goto fail;
        }
        if (msg_id > 0xFFu || entries[msg_id].type != NULL) {
            PyErr_Format(PyExc_ValueError, "entry: message id %u out of range or twice", msg_id);
            goto fail;
        }
        if (configure_entry(&entries[msg_id], cls, codes, slots, seed) != 0) {
            goto fail;
        }
    }
    Py_RETURN_NONE;
fail:
    clear_entries();
    longest_run = 0;
    return NULL;
}

static PyObject *py_cobs_decode(PyObject *module, PyObject *arg)
{
    (void)module;
    Py_buffer view;
    if (PyObject_GetBuffer(arg, &view, PyBUF_SIMPLE) != 0) {
        return NULL;
    }
    PyObject *result = NULL;
    if (view.len > RUN_CAP) {
        PyErr_Format(PyExc_ValueError, "at most %d bytes", RUN_CAP);
    } else {
        uint8_t body[BODY_CAP];
        Py_ssize_t size = cobs_decode((const uint8_t *)view.buf, view.len, body, BODY_CAP);
        if (size < 0) {
            PyErr_SetString(PyExc_ValueError, "bad COBS encoding");
        } else {
            result = PyBytes_FromStringAndSize((const char *)body, size);
        }
    }
    PyBuffer_Release(&view);
    return result;
}

static PyObject *py_crc16(PyObject *module, PyObject *args)
{
    (void)module;
    Py_buffer view;
    unsigned int seed;
    if (!PyArg_ParseTuple(args, "y*I", &view, &seed)) {
        return NULL;
    }
    uint16_t crc = crc16((const uint8_t *)view.buf, view.len, (uint16_t)seed);
    PyBuffer_Release(&view);
    return PyLong_FromUnsignedLong(crc);
}

static PyMethodDef methods[] = {
    {"scan", (PyCFunction)(void (*)(void))scan, METH_FASTCALL,
     "scan(data, last_seq) -> (out, tail, last_seq, frames, gaps, zeros, others)."},
    {"configure", configure, METH_VARARGS,
     "configure(entries, longest_run, pause_frames): entries are (msg_id, class, struct "
     "codes, slot descriptors, CRC seed) of the fixed-length messages built here."},
    {"cobs_decode", py_cobs_decode, METH_O, "cobs_decode(run) -> body (for tests)."},
    {"crc16", py_crc16, METH_VARARGS, "crc16(data, seed) -> int, as binascii.crc_hqx (tests)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT, "_cdecode", "C accelerator of the stream decoder's frame scan.",
    -1, methods, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__cdecode(void)
{
    make_crc_table();
    if (empty_tuple == NULL) {
        empty_tuple = PyTuple_New(0);
        if (empty_tuple == NULL) {
            return NULL;
        }
    }
    return PyModule_Create(&module_def);
}
