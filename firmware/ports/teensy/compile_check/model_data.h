// The shape of the header `xxd -i -n nlsoft_model app/models/<p>.nlsm`
// writes next to the sketch; one byte stands in for the model here.
unsigned char nlsoft_model[] = {0};
unsigned int nlsoft_model_len = 1;
