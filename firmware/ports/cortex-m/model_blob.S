/* The platform's shipped model file, embedded as read-only bytes so the
 * image boots ready to run. NLSOFT_MODEL_FILE is the quoted path, set by the
 * build only when app/models/<platform>.nlsm exists. */
    .section .rodata.nlsoft_model, "a"
    .balign 4
    .global nlsoft_model_begin
nlsoft_model_begin:
    .incbin NLSOFT_MODEL_FILE
    .global nlsoft_model_end
nlsoft_model_end:
    .section .note.GNU-stack, "", %progbits
