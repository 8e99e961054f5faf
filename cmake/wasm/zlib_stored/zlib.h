#pragma once
/* The part of zlib's interface Fulcrum uses (src/io/html_writer.cpp), for the
   WebAssembly build: a valid zlib stream of stored (uncompressed) deflate
   blocks (cmake/wasm/README.md). */
#ifdef __cplusplus
extern "C" {
#endif
typedef unsigned char Bytef;
typedef unsigned long uLong;
typedef unsigned long uLongf;
#define Z_OK 0
#define Z_BUF_ERROR (-5)
#define Z_BEST_COMPRESSION 9
uLong compressBound(uLong sourceLen);
int compress2(Bytef* dest, uLongf* destLen, const Bytef* source, uLong sourceLen, int level);
#ifdef __cplusplus
}
#endif
