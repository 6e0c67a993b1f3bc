"""tf.listener (belvedere.ros1.tf)."""

from belvedere.ros1.tf import Transformer, TransformerROS, TransformListener

__all__ = ["TransformListener", "Transformer", "TransformerROS"]
