// Readers and writers of test files; see FORMATS.md.
