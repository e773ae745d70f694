"""Models the pipeline can train, by name (`scripts/train.sh <model>`). A model provides
predict(batch, iterations), target(batch), sample_iterations(rng), eval_iterations() and
export_weights(path, training), and may set default_losses / default_clip (train.py's
defaults for --losses / --clip); see models/tnnd.py and models/rae.py."""
from .rae import RAE
from .tnnd import TNND

MODELS = {"tnnd": TNND, "rae": RAE}


def create(name: str, **kwargs):
    if name not in MODELS:
        raise ValueError(f"unknown model '{name}' (expected one of {', '.join(MODELS)})")
    return MODELS[name](**kwargs)
