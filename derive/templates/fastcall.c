
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

typedef void (*chaplygin_routine)(double, const double *, const double *, double *);

/* the data of an aligned, C-contiguous float64 vector of n elements, or NULL */
static double *vector(PyObject *o, npy_intp n, int writeable)
{
    if (!PyArray_CheckExact(o))
        return NULL;
    PyArrayObject *a = (PyArrayObject *)o;
    if (PyArray_TYPE(a) != NPY_DOUBLE || PyArray_SIZE(a) != n || PyArray_NDIM(a) != 1
        || !PyArray_IS_C_CONTIGUOUS(a) || !PyArray_ISALIGNED(a)
        || (writeable && !PyArray_ISWRITEABLE(a)))
        return NULL;
    return (double *)PyArray_DATA(a);
}

static PyObject *call(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 8) {
        PyErr_SetString(PyExc_TypeError, "call(address, n_out, n_state, n_param, t, y, p, out)");
        return NULL;
    }
    void *address = PyLong_AsVoidPtr(args[0]);
    npy_intp n_out = PyLong_AsSsize_t(args[1]);
    npy_intp n_state = PyLong_AsSsize_t(args[2]);
    npy_intp n_param = PyLong_AsSsize_t(args[3]);
    if (PyErr_Occurred())
        return NULL;
    double t;
    if (PyFloat_Check(args[4]))
        t = PyFloat_AS_DOUBLE(args[4]);
    else if (PyLong_CheckExact(args[4])) {
        t = PyLong_AsDouble(args[4]);
        if (t == -1.0 && PyErr_Occurred())
            return NULL;
    } else
        Py_RETURN_NOTIMPLEMENTED;
    double *y = vector(args[5], n_state, 0);
    double *p = vector(args[6], n_param, 0);
    if (y == NULL || p == NULL)
        Py_RETURN_NOTIMPLEMENTED;
    PyObject *out = args[7];
    if (out == Py_None) {
        out = PyArray_SimpleNew(1, &n_out, NPY_DOUBLE);
        if (out == NULL)
            return NULL;
    } else {
        if (vector(out, n_out, 1) == NULL)
            Py_RETURN_NOTIMPLEMENTED;
        Py_INCREF(out);
    }
    ((chaplygin_routine)address)(t, y, p, (double *)PyArray_DATA((PyArrayObject *)out));
    return out;
}

static PyMethodDef methods[] = {
    {"call", (PyCFunction)(void (*)(void))call, METH_FASTCALL,
     "call(address, n_out, n_state, n_param, t, y, p, out)"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "chaplygin_fastcall", NULL, -1,
                                    methods};

PyMODINIT_FUNC PyInit_chaplygin_fastcall(void)
{
    import_array();
    return PyModule_Create(&module);
}
