/* Wine 8.0 has no bcryptprimitives.dll, whose ProcessPrng Rust's std (1.78 and later) takes
 * its random numbers from; without it every Windows build exits 53 before printing a word
 * under Wine. This stand-in, for testing under Wine only (never shipped), answers with
 * RtlGenRandom (advapi32!SystemFunction036), which Wine has. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length)
{
    while (length > 0) {
        ULONG chunk = length > 0x40000000 ? 0x40000000 : (ULONG)length;
        if (!SystemFunction036(data, chunk))
            return FALSE;
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
