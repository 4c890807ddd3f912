/* A minimal FMI 2.0 Co-Simulation importer, the same source for Linux (dlopen) and Windows
 * (LoadLibrary): tests/python/test_platforms.py compiles it with gcc and with mingw-w64, runs the
 * Windows build under wine on binaries/win64/ViscoSPH.dll and the Linux build on
 * binaries/linux64/ViscoSPH.so, and compares the printed outputs.
 *
 * usage: importer LIBRARY GUID STOP_TIME STEP OUTPUT_VRS [r:VR=VALUE | i:VR=VALUE | s:VR=TEXT]...
 *   OUTPUT_VRS is a comma-separated list of Real value references.
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
    fmi2ValueReference out[64];
    fmi2Real values[64];
    size_t n_out = 0;
    double stop, step, t = 0.0;
    long k, n_steps;
    int a;
    char *list, *tok;
    lib_t lib;
    fmi2Component c;
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};

    if (argc < 6) {
        fprintf(stderr, "usage: importer LIBRARY GUID STOP_TIME STEP OUTPUT_VRS [r:VR=X|i:VR=N|s:VR=TEXT]...\n");
        return 2;
    }
    stop = atof(argv[3]);
    step = atof(argv[4]);
    list = argv[5];
    for (tok = strtok(list, ","); tok && n_out < 64; tok = strtok(NULL, ","))
        out[n_out++] = (fmi2ValueReference)strtoul(tok, NULL, 10);

    lib = open_lib(argv[1]);
    if (!lib) {
        fprintf(stderr, "importer: cannot load %s\n", argv[1]);
        return 3;
    }
    LOAD(instantiate_t, instantiate, "fmi2Instantiate");
    LOAD(setup_t, setup, "fmi2SetupExperiment");
    LOAD(comp_t, enter_init, "fmi2EnterInitializationMode");
    LOAD(comp_t, exit_init, "fmi2ExitInitializationMode");
    LOAD(comp_t, terminate, "fmi2Terminate");
    LOAD(free_t, free_instance, "fmi2FreeInstance");
    LOAD(set_real_t, set_real, "fmi2SetReal");
    LOAD(get_real_t, get_real, "fmi2GetReal");
    LOAD(set_int_t, set_integer, "fmi2SetInteger");
    LOAD(set_str_t, set_string, "fmi2SetString");
    LOAD(do_step_t, do_step, "fmi2DoStep");

    c = instantiate("importer", 1 /* fmi2CoSimulation */, argv[2], "", &cb, 0, 0);
    if (!c) {
        fprintf(stderr, "importer: fmi2Instantiate failed\n");
        return 3;
    }
    CHECK(setup(c, 0, 0.0, 0.0, 1, stop));
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
            fmi2Real x = atof(eq + 1);
            CHECK(set_real(c, &vr, 1, &x));
        } else if (kind == 'i') {
            fmi2Integer i = atoi(eq + 1);
            CHECK(set_integer(c, &vr, 1, &i));
        } else if (kind == 's') {
            fmi2String s = eq + 1;
            CHECK(set_string(c, &vr, 1, &s));
        } else {
            fprintf(stderr, "importer: bad setting '%s'\n", argv[a]);
            return 2;
        }
    }
    CHECK(enter_init(c));
    CHECK(exit_init(c));
    n_steps = (long)(stop / step + 0.5);
    for (k = 0; k < n_steps; k++) {
        double t_next = (k + 1) * step;
        size_t j;
        CHECK(do_step(c, t, t_next - t, 1));
        t = t_next;
        CHECK(get_real(c, out, n_out, values));
        printf("%.17g", t);
        for (j = 0; j < n_out; j++)
            printf(",%.17g", values[j]);
        printf("\n");
    }
    CHECK(terminate(c));
    free_instance(c);
    return 0;
}
