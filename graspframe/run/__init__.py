"""One grasp run, from request to result.json: what a run is asked and everything it
needs, looked up before it starts (`request`), the stages (`stages`), run in order by
`runner`, what each stage hands on and the result (`result`), the score (`scoring`), the
run folder (`folder`), the scene file (`scene`) and the bundled demo (`demo/`)."""
