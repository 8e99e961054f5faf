// tinygltf's implementation for the WebAssembly build: glTF JSON and GLB only
// (Fulcrum's files hold no images, so no image codecs).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
