/* compress2 as stored deflate blocks (RFC 1950 header and Adler-32 trailer,
   RFC 1951 blocks of type 0): see zlib.h here. */
#include "zlib.h"

#define BLOCK 65535u

uLong compressBound(uLong sourceLen) {
    uLong blocks = sourceLen / BLOCK + 1;
    return 2 + blocks * 5 + sourceLen + 4;
}

int compress2(Bytef* dest, uLongf* destLen, const Bytef* source, uLong sourceLen, int level) {
    (void)level;
    if (*destLen < compressBound(sourceLen)) return Z_BUF_ERROR;
    Bytef* out = dest;
    *out++ = 0x78; /* deflate, 32 KiB window */
    *out++ = 0x01; /* no dictionary, fastest; 0x7801 is a multiple of 31 */
    uLong a = 1, b = 0, done = 0;
    do {
        uLong n = sourceLen - done < BLOCK ? sourceLen - done : BLOCK;
        *out++ = done + n == sourceLen ? 1 : 0; /* BFINAL, BTYPE = 00 */
        *out++ = (Bytef)(n & 0xFF);
        *out++ = (Bytef)(n >> 8);
        *out++ = (Bytef)(~n & 0xFF);
        *out++ = (Bytef)((~n >> 8) & 0xFF);
        for (uLong i = 0; i < n; ++i) {
            Bytef c = source[done + i];
            *out++ = c;
            a = (a + c) % 65521u;
            b = (b + a) % 65521u;
        }
        done += n;
    } while (done < sourceLen);
    *out++ = (Bytef)(b >> 8);
    *out++ = (Bytef)b;
    *out++ = (Bytef)(a >> 8);
    *out++ = (Bytef)a;
    *destLen = (uLongf)(out - dest);
    return Z_OK;
}
