"""Models the pipeline can train, by name (`scripts/train.sh <model>`). A model provides
predict(batch, iterations), target(batch), sample_iterations(rng), eval_iterations() and
export_weights(path, training); see models/tnnd.py. The RAE (issue 17) registers here too."""
from .tnnd import TNND

MODELS = {"tnnd": TNND}


def create(name: str, **kwargs):
    if name not in MODELS:
        raise ValueError(f"unknown model '{name}' (expected one of {', '.join(MODELS)})")
    return MODELS[name](**kwargs)
