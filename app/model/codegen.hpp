#pragma once
// `model codegen`: a model file as a C++ header the firmware compiles in.
// The parameters become one `const float` array (flash on an MCU), plus a
// function that fills a shared/model.hpp Model view over it - no heap, no
// file system, the same numbers the file carries.
#include <string>

#include "app/model/model_store.hpp"

namespace nlsoft::pipeline {

// `ns` is the namespace the header declares (a C++ identifier); `source`
// names the model file in the header comment. Throws PipelineError.
std::string generate_header(const ModelFile& model, const std::string& ns, const std::string& source);

}  // namespace nlsoft::pipeline
