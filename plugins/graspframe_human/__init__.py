"""Built-in graspframe plugin: the human right hand, the reference hand for scoring."""
