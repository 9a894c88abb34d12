"""From errors to scores: the paper's weighted scores, and simpick's verdict over real runs."""
