/* Stand-in for Windows' bcryptprimitives.dll, for running the win64 FMU under wine only.
 *
 * Rust's standard library for x86_64-pc-windows-gnu (Windows 10 and later) draws its random
 * seeds (HashMap keys) from ProcessPrng in bcryptprimitives.dll, which every Windows 10/11 has
 * but Debian 12's wine 8.0 does not ship. tests/python/test_platforms.py compiles this file
 * next to the Windows test importer, where the loader finds it first; on Windows the system's
 * DLL is used and this file plays no part. ProcessPrng is implemented with RtlGenRandom
 * (advapi32's SystemFunction036), which wine has. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    while (length > 0) {
        ULONG n = length > 0x40000000 ? 0x40000000 : (ULONG)length;
        if (!SystemFunction036(data, n))
            return FALSE;
        data += n;
        length -= n;
    }
    return TRUE;
}
