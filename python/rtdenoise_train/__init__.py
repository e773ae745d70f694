"""rtdenoise_train: the training pipeline of rtdenoise's learned methods (docs/training.md).

A client of the library, like the renderer: it reads the data set that `rtdenoise dataset`
writes (through its training cache), trains a model with PyTorch and writes the weights file
that the library's method reads (for TNND: src/methods/tnnd/tnnd_weights.json)."""
