/* A minimal FMI 2.0 and FMI 3.0 Co-Simulation importer, the same source for Linux (dlopen) and
 * Windows (LoadLibrary): tests/python/test_platforms.py compiles it with gcc, with mingw-w64 and
 * with aarch64-linux-gnu-gcc, runs the Windows build under wine on the win64 / x86_64-windows
 * DLL, the aarch64 build under qemu-aarch64 on binaries/aarch64-linux/ViscoSPH.so and the Linux
 * build on the x86_64 library, and compares the printed outputs.
 *
 * usage: importer [--fmi3] LIBRARY GUID STOP_TIME STEP OUTPUT_VRS [r:VR=X | i:VR=N | s:VR=TEXT]...
 *   OUTPUT_VRS is a comma-separated list of Real (Float64) value references; with --fmi3 the
 *   FMI 3.0 functions are called (GUID is then the instantiationToken, i: sets an Int32).
 * Prints one line per communication point: the time, then each output, as %.17g (round-trips a
 * double exactly). Exit status 0 on success, 2 on a usage error, 3 if a call fails. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#include <windows.h>
typedef HMODULE lib_t;
static lib_t open_lib(const char *p) { return LoadLibraryA(p); }
static void *sym(lib_t l, const char *n) { return (void *)GetProcAddress(l, n); }
#else
#include <dlfcn.h>
typedef void *lib_t;
static lib_t open_lib(const char *p) { return dlopen(p, RTLD_NOW | RTLD_LOCAL); }
static void *sym(lib_t l, const char *n) { return dlsym(l, n); }
#endif

/* Room for every output the FMU declares (the load along the plate alone has 48). */
#define MAX_OUTPUTS 1024

typedef void *fmi2Component;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef const char *fmi2String;
typedef int fmi2Status; /* fmi2OK = 0, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending */

typedef struct {
    void (*logger)(void *, fmi2String, fmi2Status, fmi2String, fmi2String, ...);
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} fmi2CallbackFunctions;

static void logger(void *env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    va_list ap;
    (void)env;
    fprintf(stderr, "[%s %d %s] ", name, status, category);
    va_start(ap, message);
    vfprintf(stderr, message, ap);
    va_end(ap);
    fputc('\n', stderr);
}

typedef fmi2Component (*instantiate_t)(fmi2String, int, fmi2String, fmi2String,
                                       const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean);
typedef fmi2Status (*setup_t)(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean,
                              fmi2Real);
typedef fmi2Status (*comp_t)(fmi2Component);
typedef void (*free_t)(fmi2Component);
typedef fmi2Status (*set_real_t)(fmi2Component, const fmi2ValueReference *, size_t,
                                 const fmi2Real *);
typedef fmi2Status (*get_real_t)(fmi2Component, const fmi2ValueReference *, size_t, fmi2Real *);
typedef fmi2Status (*set_int_t)(fmi2Component, const fmi2ValueReference *, size_t,
                                const fmi2Integer *);
typedef fmi2Status (*set_str_t)(fmi2Component, const fmi2ValueReference *, size_t,
                                const fmi2String *);
typedef fmi2Status (*do_step_t)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);

/* FMI 3.0 (fmi3Functions.h): the functions whose arguments differ from FMI 2.0's. */
typedef void (*log3_t)(void *, int, const char *, const char *);
typedef void *(*instantiate3_t)(const char *, const char *, const char *, _Bool, _Bool, _Bool,
                                _Bool, const unsigned int *, size_t, void *, log3_t, void *);
typedef int (*enter_init3_t)(void *, _Bool, double, double, _Bool, double);
typedef int (*set_real3_t)(void *, const unsigned int *, size_t, const double *, size_t);
typedef int (*get_real3_t)(void *, const unsigned int *, size_t, double *, size_t);
typedef int (*set_int3_t)(void *, const unsigned int *, size_t, const int *, size_t);
typedef int (*set_str3_t)(void *, const unsigned int *, size_t, const char *const *, size_t);
typedef int (*do_step3_t)(void *, double, double, _Bool, _Bool *, _Bool *, _Bool *, double *);

static void logger3(void *env, int status, const char *category, const char *message) {
    (void)env;
    fprintf(stderr, "[%d %s] %s\n", status, category, message);
}

/* The calls the run makes, bound to one FMI version's functions. */
static lib_t lib;
static int fmi3;
static set_real_t set_real;
static get_real_t get_real;
static set_int_t set_integer;
static set_str_t set_string;
static do_step_t do_step;
static set_real3_t set_real3;
static get_real3_t get_real3;
static set_int3_t set_int3;
static set_str3_t set_str3;
static do_step3_t do_step3;
static enter_init3_t enter_init3_fn;

static int set_r(void *c, fmi2ValueReference vr, double x) {
    return fmi3 ? set_real3(c, &vr, 1, &x, 1) : set_real(c, &vr, 1, &x);
}
static int set_i(void *c, fmi2ValueReference vr, int i) {
    return fmi3 ? set_int3(c, &vr, 1, &i, 1) : set_integer(c, &vr, 1, &i);
}
static int set_s(void *c, fmi2ValueReference vr, const char *s) {
    return fmi3 ? set_str3(c, &vr, 1, &s, 1) : set_string(c, &vr, 1, &s);
}
static int get_r(void *c, const fmi2ValueReference *vr, size_t n, double *v) {
    return fmi3 ? get_real3(c, vr, n, v, n) : get_real(c, vr, n, v);
}
static int step_to(void *c, double t, double h) {
    _Bool event, terminate, early;
    double last;
    return fmi3 ? do_step3(c, t, h, 1, &event, &terminate, &early, &last) : do_step(c, t, h, 1);
}

#define LOAD(type, var, name)                                                  \
    type var = (type)sym(lib, name);                                           \
    if (!var) {                                                                \
        fprintf(stderr, "importer: %s is not exported\n", name);               \
        return 3;                                                              \
    }
#define CHECK(call)                                                            \
    do {                                                                       \
        fmi2Status st_ = (call);                                               \
        if (st_ != 0) {                                                        \
            fprintf(stderr, "importer: %s returned %d\n", #call, st_);         \
            return 3;                                                          \
        }                                                                      \
    } while (0)

int main(int argc, char **argv) {
    fmi2ValueReference out[MAX_OUTPUTS];
    fmi2Real values[MAX_OUTPUTS];
    size_t n_out = 0;
    double stop, step, t = 0.0;
    long k, n_steps;
    int a;
    char *list, *tok;
    void *c;
    comp_t enter_init, exit_init, terminate;
    free_t free_instance;
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};

    fmi3 = argc > 1 && strcmp(argv[1], "--fmi3") == 0;
    argv += fmi3;
    argc -= fmi3;
    if (argc < 6) {
        fprintf(stderr, "usage: importer [--fmi3] LIBRARY GUID STOP_TIME STEP OUTPUT_VRS [r:VR=X|i:VR=N|s:VR=TEXT]...\n");
        return 2;
    }
    stop = atof(argv[3]);
    step = atof(argv[4]);
    list = argv[5];
    for (tok = strtok(list, ","); tok; tok = strtok(NULL, ",")) {
        if (n_out == MAX_OUTPUTS) {
            fprintf(stderr, "importer: more than %d outputs\n", MAX_OUTPUTS);
            return 2;
        }
        out[n_out++] = (fmi2ValueReference)strtoul(tok, NULL, 10);
    }

    lib = open_lib(argv[1]);
    if (!lib) {
        fprintf(stderr, "importer: cannot load %s\n", argv[1]);
        return 3;
    }
    if (fmi3) {
        LOAD(instantiate3_t, instantiate3, "fmi3InstantiateCoSimulation");
        LOAD(enter_init3_t, enter_init3, "fmi3EnterInitializationMode");
        LOAD(comp_t, exit3, "fmi3ExitInitializationMode");
        LOAD(comp_t, terminate3, "fmi3Terminate");
        LOAD(free_t, free3, "fmi3FreeInstance");
        LOAD(set_real3_t, sr3, "fmi3SetFloat64");
        LOAD(get_real3_t, gr3, "fmi3GetFloat64");
        LOAD(set_int3_t, si3, "fmi3SetInt32");
        LOAD(set_str3_t, ss3, "fmi3SetString");
        LOAD(do_step3_t, ds3, "fmi3DoStep");
        set_real3 = sr3, get_real3 = gr3, set_int3 = si3, set_str3 = ss3, do_step3 = ds3;
        exit_init = exit3, terminate = terminate3, free_instance = free3;
        c = instantiate3("importer", argv[2], "", 0, 0, 0, 0, NULL, 0, NULL, logger3, NULL);
        if (!c) {
            fprintf(stderr, "importer: fmi3InstantiateCoSimulation failed\n");
            return 3;
        }
        /* fmi3EnterInitializationMode takes the experiment: called after the settings below */
        enter_init = NULL;
        enter_init3_fn = enter_init3;
    } else {
        LOAD(instantiate_t, instantiate, "fmi2Instantiate");
        LOAD(setup_t, setup, "fmi2SetupExperiment");
        LOAD(comp_t, enter2, "fmi2EnterInitializationMode");
        LOAD(comp_t, exit2, "fmi2ExitInitializationMode");
        LOAD(comp_t, terminate2, "fmi2Terminate");
        LOAD(free_t, free2, "fmi2FreeInstance");
        LOAD(set_real_t, sr, "fmi2SetReal");
        LOAD(get_real_t, gr, "fmi2GetReal");
        LOAD(set_int_t, si, "fmi2SetInteger");
        LOAD(set_str_t, ss, "fmi2SetString");
        LOAD(do_step_t, ds, "fmi2DoStep");
        set_real = sr, get_real = gr, set_integer = si, set_string = ss, do_step = ds;
        enter_init = enter2, exit_init = exit2, terminate = terminate2, free_instance = free2;
        c = instantiate("importer", 1 /* fmi2CoSimulation */, argv[2], "", &cb, 0, 0);
        if (!c) {
            fprintf(stderr, "importer: fmi2Instantiate failed\n");
            return 3;
        }
        CHECK(setup(c, 0, 0.0, 0.0, 1, stop));
    }
    for (a = 6; a < argc; a++) {
        char kind = argv[a][0];
        char *eq = strchr(argv[a], '=');
        fmi2ValueReference vr;
        if (strlen(argv[a]) < 4 || argv[a][1] != ':' || !eq) {
            fprintf(stderr, "importer: bad setting '%s'\n", argv[a]);
            return 2;
        }
        vr = (fmi2ValueReference)strtoul(argv[a] + 2, NULL, 10);
        if (kind == 'r') {
            CHECK(set_r(c, vr, atof(eq + 1)));
        } else if (kind == 'i') {
            CHECK(set_i(c, vr, atoi(eq + 1)));
        } else if (kind == 's') {
            CHECK(set_s(c, vr, eq + 1));
        } else {
            fprintf(stderr, "importer: bad setting '%s'\n", argv[a]);
            return 2;
        }
    }
    if (fmi3)
        CHECK(enter_init3_fn(c, 0, 0.0, 0.0, 1, stop));
    else
        CHECK(enter_init(c));
    CHECK(exit_init(c));
    n_steps = (long)(stop / step + 0.5);
    for (k = 0; k < n_steps; k++) {
        double t_next = (k + 1) * step;
        size_t j;
        CHECK(step_to(c, t, t_next - t));
        t = t_next;
        CHECK(get_r(c, out, n_out, values));
        printf("%.17g", t);
        for (j = 0; j < n_out; j++)
            printf(",%.17g", values[j]);
        printf("\n");
    }
    CHECK(terminate(c));
    free_instance(c);
    return 0;
}
