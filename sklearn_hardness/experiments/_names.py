"""The experiments' names and help texts, importable without torch or scikit-learn.

The command line builds its parser and ``reproduce --help`` from them (in well
under a second, without importing the library), and
:func:`~sklearn_hardness.experiments.get_config`'s docstring is written from
:data:`CONFIG_KEYS`. Nothing here may import anything beyond the standard library.
"""

#: The named pipelines the paper's experiments (``reproduce --model``, ``model=``) can run: their runner
#: trains the pipeline's last step on inputs prepared once per dataset (names of
#: :func:`sklearn_hardness.models.pipeline_names`).
EXPERIMENT_MODELS = ("convlstm", "ofnn", "dinov2nn", "contact_profile_nn", "contact_profile", "contact_profile_3",
                     "contact_geometry", "loading_compliance")

#: The strategies compared by default (BALD is our addition to the paper's three).
STRATEGIES = ("variance", "entropy", "random", "bald")

#: What ``--quick`` / ``quick=True`` changes: smaller simulated images and
#: frames, fewer epochs, MC passes and runs. Same algorithm, same presets.
QUICK_OVERRIDES = {
    "image_size": (96, 128),
    "frame_size": (12, 16),
    "initial_epochs": 40,
    "epochs_per_query": 10,
    "lr": 3e-3,
    "n_samples": 10,
    "n_runs": 1,
}


#: One line per configuration key: get_config's docstring and ``reproduce --help`` are made from it.
CONFIG_KEYS = {
    "model": f"classifier, a named pipeline among {', '.join(EXPERIMENT_MODELS)} (models.pipeline_info "
             "says what each is; the presets: convlstm for silicone5, dinov2nn for shore9); the logistic heads "
             "(contact_profile, contact_profile_3, contact_geometry, loading_compliance) are refitted at each "
             "iteration: epochs, "
             "lr, dropout and batch_size do not apply; loading_compliance needs each press's force and position",
    "n_initial": "s0: presses per reference object in the initial training set",
    "n_per_query": "s: presses of the queried object added per iteration",
    "n_iterations": "N: active-sampling iterations",
    "n_test": "l: presses of the test object the strategies look at",
    "n_holdout": "presses per object held out of every run and scored after each iteration (0: none)",
    "n_runs": "seeds per test object",
    "initial_epochs": "e0: epochs of the initial training",
    "epochs_per_query": "e: epochs per iteration (an upper bound with early_stopping)",
    "max_reservoir": "M: at most M reservoir presses trained on per iteration (None: all)",
    "n_samples": "n: MC-dropout passes per query",
    "n_ensemble": "0: MC dropout (the paper); k >= 2: an ensemble of k differently seeded nets",
    "dropout": "dropout rate (the paper: 0.2)",
    "class_weight": "class weights of the classifier: None, the paper's unweighted loss (default), or "
                    "'balanced', the ready-made pipelines' default for imbalanced classes",
    "lr": "learning rate",
    "batch_size": "training batch size (None: the model's, 8 ConvLSTM, 32 MLP heads)",
    "early_stopping": "k: training after the initial one stops when the loss has not improved for k "
                      "epochs (None: every epoch)",
    "convergence_threshold": "runs whose initial training loss exceeds it are skipped ('auto': for the "
                             "ConvLSTM 1.0 at 5 classes, the same fraction of chance loss ln K at K classes "
                             "(models.is_converged with threshold='chance'); None otherwise)",
    "dropout_placement": "ConvLSTM only: 'head' (on the pooled features, default), 'layers' (after each "
                         "ConvLSTM layer, the paper's) or 'channels' (one mask per channel map)",
    "n_between": "frames kept between the first and the last contact frame",
    "frame_size": "(height, width) of the selected frames (None: the model's, 12x16 for the ConvLSTM)",
    "color": "'gray' or 'rgb' frames (None: the model's)",
    "crop_contact": "f in (0, 1): cut each press to f x the frame around its contact (None: whole frames)",
    "input_scale": "'std': the ConvLSTM's FrameScaler, fitted on each run's training presses; None: raw frames",
    "dinov2_model": "DINOv2 weights: a Hugging Face id in the local cache or a local folder",
    "device": "torch device of the named models: cpu, cuda, cuda:1 or auto",
    "image_size": "(height, width) of simulated frames",
    "data_seed": "seed of the simulated presses",
}
