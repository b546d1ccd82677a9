// tinygltf's declarations as every file of ours sees them: its options change what its
// header declares (TinyGLTF's default image writer), so each file that includes
// <tiny_gltf.h> includes it through here. Its implementation is compiled in gltf.cpp
// alone (docs/build-notes.md).
#pragma once

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
