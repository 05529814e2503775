#pragma once
// A model's size in the one wording every command uses (`model info`,
// `train`, `model upload`): the network's weights and the normalisation
// floats a model file carries beside them, never one count for both.
#include <cstdint>
#include <string>

namespace nlsoft::console {

// "915 weights + 78 normalisation = 993 floats", from the file's float count
// (Model::param_count) and its normalisation part (Model::norm_count()).
inline std::string model_size_words(uint32_t floats, uint32_t normalisation) {
  return std::to_string(floats - normalisation) + " weights + " + std::to_string(normalisation) +
         " normalisation = " + std::to_string(floats) + " floats";
}

}  // namespace nlsoft::console
